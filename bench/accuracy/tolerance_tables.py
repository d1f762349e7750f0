#!/usr/bin/env python3
"""Markdown tables for docs/accuracy.md ("Accuracy on demand") from the
output of bench/accuracy/tolerance_sweep (its stdout and its --csv):

    tolerance_sweep --csv cells.csv > sweep.txt
    bench/accuracy/tolerance_tables.py sweep.txt cells.csv

A (scene, tolerance) is judged only when the converged reference is known
to better than a third of the tolerance (its uncertainty, the difference
between the reference and a run at twice its step); the others are listed
with that reason. Cost is given two ways: wall time (one run per cell on a
shared machine, noisy) and force evaluations per simulated second (exact,
the oracle's measure and the bar's)."""
import csv
import re
import sys
from collections import defaultdict

head = re.compile(r"^## (\S+): reference (\S+) dt (\S+) \(uncertainty (\S+)\)")
row = re.compile(r"^tol (\S+)\s+chose (\S+)\s+dt (\S+)\s+pred (\S+) real (\S+) \| oracle (\S+)\s+dt (\S+)\s+cost x(\S+)"
                 r"(?: evals x(\S+))? \| estimate (\S+) \(x(\S+), shadow (\d+)%")
# a choice on another model than the scene's (its name, '_' for spaces, and
# the bound of its converged solution's distance from the scene's)
swapped = re.compile(r"\| model (\S+) gap (\S+)")


def main(sweep, cells_path):
    cells = defaultdict(list)
    with open(cells_path) as f:
        for c in csv.DictReader(f):
            cells[c["scene"]].append(c)
    rows, uncert = [], {}
    scene = None
    for line in open(sweep):
        if m := head.match(line):
            scene = m[1]
            uncert[scene] = float(m[4])
        elif m := row.match(line):
            sw = swapped.search(line)
            rows.append(dict(scene=scene, tol=float(m[1]), kind=m[2], dt=float(m[3]), pred=float(m[4]),
                             real=float(m[5]), okind=m[6], odt=float(m[7]), cost=float(m[8]),
                             eratio=float(m[9]) if m[9] else None, est=float(m[10]), ratio=float(m[11]),
                             shadow=int(m[12]), model=sw[1].replace("_", " ") if sw else None,
                             gap=float(sw[2]) if sw else None))

    def evals(r, kind, dt, error=None):
        best = None
        for c in cells[r["scene"]]:
            if c["kind"] != kind or abs(float(c["dt"]) / dt - 1) > 5e-3 or c["healthy"] != "1":
                continue
            if error is None or best is None or abs(float(c["error"]) - error) < abs(float(best["error"]) - error):
                best = c
        return float(best["evals"]) if best else None

    for tol in sorted({r["tol"] for r in rows}, reverse=True):
        print(f"\n#### Tolerance {tol:g}\n")
        print("| scene | chosen | predicted | realised | within | cost / oracle (wall) | evals / oracle | "
              "estimate / realised |")
        print("|---|---|---|---|---|---|---|---|")
        judged = within = over3 = cheap = est3 = 0
        skipped = []
        for r in (r for r in rows if r["tol"] == tol):
            if uncert[r["scene"]] > tol / 3:
                skipped.append(f"{r['scene']} (reference known to {uncert[r['scene']]:.1e})")
                continue
            judged += 1
            ok = r["real"] <= tol
            within += ok
            over3 += r["real"] > 3 * tol
            e_chosen = evals(r, r["kind"], r["dt"], r["real"])
            e_oracle = evals(r, r["okind"], r["odt"]) if r["okind"] != "-" else None
            eratio = r["eratio"] if r["eratio"] is not None else (
                e_chosen / e_oracle if e_chosen and e_oracle else None)
            # the bar is on force evaluations (exact; the chooser's own cost)
            cheap += r["okind"] != "-" and eratio is not None and eratio <= 2 + 1e-9
            est3 += 1 / 3 <= r["ratio"] <= 3
            chosen = f"{r['kind']} {r['dt']:.3g}" + (f" on {r['model']} (gap {r['gap']:.1e})" if r["model"] else "")
            print(f"| {r['scene']} | {chosen} | {r['pred']:.2e} | {r['real']:.2e} | "
                  f"{'yes' if ok else '**no**'} | {r['cost']:.2f} | {f'{eratio:.2f}' if eratio else '-'} | "
                  f"{r['ratio']:.2f} |")
        print(f"\nJudged {judged}: within the tolerance {within} ({100 * within / max(judged, 1):.0f}%), "
              f"more than 3x over {over3}; cost (force evaluations) within 2x of the oracle's {cheap}; "
              f"estimate within 3x of the realised error {est3} ({100 * est3 / max(judged, 1):.0f}%).")
        if skipped:
            print("Not judged (no converged reference at this tolerance): " + ", ".join(skipped) + ".")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
