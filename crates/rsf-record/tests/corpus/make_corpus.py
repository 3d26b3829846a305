"""Writes the reader's regression corpus into this folder (run from here: python3 make_corpus.py).

Twenty rows of (time_s, lp_um, mu) in the export variants lab software writes, and reproducers
of the broken files of issue 20, each with its expected outcome in expected.json.
"""
import json
import math

rows = [(round(i * 0.1, 1), round(100 + 0.3 * i, 3), round(0.6 + 0.001 * math.sin(i), 6)) for i in range(20)]


def body(sep=",", dec=".", eol="\n", trail="", idx=False):
    out = []
    for i, r in enumerate(rows):
        line = "{:.1f}{s}{:.3f}{s}{:.6f}".format(*r, s=sep)
        if dec != ".":
            line = line.replace(".", dec)
        if idx:
            line = f"{i}{sep}" + line
        out.append(line + trail)
    return eol.join(out) + eol


H = "time_s{s}lp_um{s}mu"
cases = {}


def add(name, data, expect):
    with open(name, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())
    cases[name] = expect


ok = {"rows": 20}
add("comma.csv", H.format(s=",") + "\n" + body(), ok)
add("tab.txt", H.format(s="\t") + "\n" + body("\t"), ok)
add("semicolon_decimal_comma.csv", H.format(s=";") + "\n" + body(";", ","), ok)
add("spaces.txt", "time_s   lp_um   mu\n" + body("   "), ok)
add("crlf.csv", (H.format(s=",") + "\n" + body()).replace("\n", "\r\n"), ok)
add("cr_only.csv", (H.format(s=",") + "\n" + body()).replace("\n", "\r"), ok)
add("bom_excel.csv", "\ufeff" + H.format(s=",") + "\r\n" + body(eol="\r\n"), ok)
add("quoted.csv", '"time_s","lp_um","mu"\n' + "".join('"' + l.replace(",", '","') + '"\n' for l in body().splitlines()), ok)
add("padded.csv", "time_s , lp_um , mu\n" + body(" , "), ok)
add("preamble_units_comments.txt",
    "Machine: BRAVA\nSample: basalt gouge\n# comment\n" + H.format(s="\t") + "\ns\tum\t-\n" + body("\t"), ok)
add("trailing_delimiter.csv", H.format(s=",") + "\n" + body(trail=","), ok)
add("leading_index_xlook.txt",
    "number of records = 20\ntime_s lp_um mu\nsec mic .\n20 recs 20 recs 20 recs\n" + body(" ", idx=True), ok)
add("no_final_newline.csv", H.format(s=",") + "\n" + body().rstrip("\n"), ok)
named = {"rows": 20, "columns": ["Time(s)", "Displ(\u00b5m)", "Friction"]}
add("windows1252_header.txt", ("Time(s)\tDispl(\u00b5m)\tFriction\n" + body("\t")).encode("cp1252"),
    dict(named, warning="Windows-1252"))
add("utf16le_bom.txt", ("Time(s)\tDispl(\u00b5m)\tFriction\r\n" + body("\t", eol="\r\n")).encode("utf-16"), named)
full = H.format(s=",") + "\n" + body()
add("cut_mid_row.csv", full[:-5], {"rows": 19, "warning": "cut line"})
add("over_range_9.9e37.csv", full.replace(f"{rows[5][2]:.6f}", "9.9e37"),
    {"error": ":7: column `mu`: 9.9e37 is out of range"})
add("sentinel.csv", full.replace(f"{rows[5][1]:.3f}", "-999999"),
    {"error": ":7: column `lp_um`: -999999 is an instrument's no-reading value"})
add("ragged_some_rows.csv", full.replace(f"\n{rows[8][0]:.1f},", f"\n{rows[8][0]:.1f},1,", 1),
    {"error": ":10: 4 fields where the header and the rows before have 3"})
add("nan_first_time.csv", full.replace("\n0.0,", "\nNaN,", 1), {"error": ":2: column `time_s`: NaN is not finite"})
add("time_not_increasing.csv", full.replace(f"\n{rows[6][0]:.1f},", "\n0.1,", 1),
    {"error": ":8: column `time_s`: time 0.1 does not increase (previous 0.5)"})
add("binary.bin", bytes(5000), {"error": "a NUL byte"})
add("header_missing.csv", body(), {"error": "no header line names the column `time_s`"})
json.dump(cases, open("expected.json", "w"), indent=1, ensure_ascii=False)
print(f"{len(cases)} files")
