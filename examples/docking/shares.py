"""Prints the share of runs docked per law and per varied key of a sweep CSV whose
`vary` sets one disturbance at a time (examples/docking/one-at-a-time.toml): a run
belongs to the key its row gives a non-zero value (the others are off).

    python3 examples/docking/shares.py one-at-a-time.csv
"""

import csv
import sys


def main(path):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        columns = reader.fieldnames
        rows = list(reader)
    keys = columns[columns.index("abs_work_j") + 1 :]
    laws = list(dict.fromkeys(r["law"] for r in rows))
    counts = {}
    for r in rows:
        on = [k for k in keys if float(r[k]) != 0.0]
        assert len(on) == 1, f"a row with {on} set: one disturbance at a time"
        n, docked = counts.get((r["law"], on[0]), (0, 0))
        counts[(r["law"], on[0])] = (n + 1, docked + int(r["docked"]))
    width = max(len(law) for law in laws)
    print(f"{'docked share':<{width}} " + " ".join(f"{k:>22}" for k in keys))
    for law in laws:
        cells = []
        for k in keys:
            n, docked = counts[(law, k)]
            cells.append(f"{100.0 * docked / n:>21.1f}%")
        print(f"{law:<{width}} " + " ".join(cells))


if __name__ == "__main__":
    main(sys.argv[1])
