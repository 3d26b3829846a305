"""The verdict of run.sh --compare: QDYN's regression cases on rsf's friction against the same
cases on QDYN's own friction, run here in the same go (suite.py's records).

Usage: python compare_suites.py OWN.json RSF.json [RSF_SUITE.log]

Prints a Markdown table per case: QDYN's own verdict against its frozen results for each
build, the largest relative deviation from the frozen run, and rsf's largest relative
deviation from QDYN's own build; a case that did not run on rsf's friction says why (the
suite's exception, and the last line rsf's friction module or QDYN wrote before stopping, from
RSF_SUITE.log). Exit status 1 when a case that passes on QDYN's own
friction does not pass on rsf's (a case that QDYN itself fails here cannot be asked of rsf),
0 otherwise.
"""

import json
import sys


def main():
    with open(sys.argv[1]) as f:
        own = json.load(f)
    with open(sys.argv[2]) as f:
        rsf = json.load(f)
    why = ""
    if len(sys.argv) > 3:
        with open(sys.argv[3], errors="replace") as f:
            stops = [line.strip() for line in f if "friction (rsf)" in line or "STOP" in line]
        if stops:
            why = "; " + stops[-1]
    print("| case | QDYN's own friction | rsf's friction | rsf vs QDYN's own (var1, var2) |")
    print("|---|---|---|---|")
    regressed = []
    for name in own["summary"]:
        o = own["summary"][name]
        r = rsf["summary"].get(name)
        cell_o = f"{'pass' if o['passed'] else 'FAIL'} ({o['dev_var1']:.1e}, {o['dev_var2']:.1e})"
        if r is None:
            cell_r, vs = "did not run" + (f": {rsf['crashed']}" if rsf.get("crashed") else "") + why, "-"
        else:
            cell_r = f"{'pass' if r['passed'] else 'FAIL'} ({r['dev_var1']:.1e}, {r['dev_var2']:.1e})"
            vs = f"{r.get('vs_other_var1', float('nan')):.1e}, {r.get('vs_other_var2', float('nan')):.1e}"
        print(f"| {name} | {cell_o} | {cell_r} | {vs} |")
        if o["passed"] and (r is None or not r["passed"]):
            regressed.append(name)
    print()
    print("(verdict: QDYN's rtol 1e-4 against its frozen results; in brackets the largest relative deviation of var1, var2)")
    if regressed:
        print(f"REGRESSED on rsf's friction: {', '.join(regressed)}")
        sys.exit(1)
    print("every case QDYN passes here on its own friction passes on rsf's")


if __name__ == "__main__":
    main()
