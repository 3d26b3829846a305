#!/usr/bin/env bash
# Renders diagnosis reports (HTML) and figures (SVG) to PNG in headless Chromium, to see them as
# a reader's browser shows them: overflow, overlapping or duplicate tick labels, raw numbers.
#
#   bash docs/diagnose/screenshot.sh FILE.html|FILE.svg ...     # writes FILE.html.png, FILE.svg.png
#   OUT_DIR=/tmp/shots bash docs/diagnose/screenshot.sh ...      # or into OUT_DIR
#   HEIGHT=5000 bash docs/diagnose/screenshot.sh report.html     # a taller page (default 3000 px)
#
# Needs Chromium (Debian: apt-get install chromium). A report is shot in a 1100 px wide window
# (it is laid out for 1000 px); an SVG at its own size, read from its width/height attributes.
set -euo pipefail
CHROME=${CHROME:-$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)}
[ -n "$CHROME" ] || { echo "screenshot.sh: no chromium found (apt-get install chromium)" >&2; exit 1; }
[ $# -gt 0 ] || { sed -n '2,10p' "$0" >&2; exit 2; }
for f in "$@"; do
    abs=$(realpath "$f")
    out=${OUT_DIR:-$(dirname "$abs")}/$(basename "$abs").png
    mkdir -p "$(dirname "$out")"
    size="1100,${HEIGHT:-3000}"
    if [[ $abs == *.svg ]]; then
        w=$(grep -o -m1 'width="[0-9]*"' "$abs" | head -1 | tr -dc 0-9)
        h=$(grep -o -m1 'height="[0-9]*"' "$abs" | head -1 | tr -dc 0-9)
        size="${w:-1000},${h:-700}"
    fi
    # --no-sandbox: Chromium refuses to run as root otherwise (containers, CI)
    "$CHROME" --headless --no-sandbox --disable-gpu --hide-scrollbars --force-device-scale-factor=1 \
        --window-size="$size" --screenshot="$out" "file://$abs" >/dev/null 2>&1
    echo "$out"
done
