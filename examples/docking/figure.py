"""Draws examples/docking/final-errors.png from the outcome CSVs of the precision sweeps
(examples/docking/README.md): for each law, the share of its runs whose final distance to
the dock (left) and |final heading error| (right) is above x (log scales: the runs
that fail the tolerance are the curve right of the grey line), on the disturbed robot
without the observer (solid), with it (dashed) and without any disturbance (dotted); the
grey lines are the tolerances, 1 cm and 1 deg.

    python examples/docking/figure.py precision.csv precision-ideal.csv examples/docking/final-errors.png

Needs matplotlib (scripts/python-test-requirements.txt).
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    """{law: ([final_dl_mm], [|final_heading_error_deg|])} of a sweep CSV."""
    out = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            dl, th = out.setdefault(row["law"], ([], []))
            dl.append(1000.0 * float(row["final_dl_m"]))
            th.append(abs(float(row["final_heading_error_deg"])))
    return out


def tail(ax, values, **style):
    """The share of the runs whose value is above x (the complement of the ECDF)."""
    v = sorted(max(x, 1e-6) for x in values)
    n = len(v)
    ax.step(v, [max((n - i - 1) / n, 0.5 / n) for i in range(n)], where="post", **style)


def main(disturbed_csv, ideal_csv, png):
    disturbed, ideal = read(disturbed_csv), read(ideal_csv)
    laws = [law for law in ideal if "#" not in law]
    colours = dict(zip(laws, ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]))
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.6), constrained_layout=True)
    for k, (ax, what, tol) in enumerate(
        zip(axes, ["final distance to the dock (mm)", "|final heading error| (deg)"], [10.0, 1.0])
    ):
        for law in laws:
            c = colours[law]
            tail(ax, disturbed[law][k], color=c, lw=1.6, label=f"{law}: disturbed")
            tail(ax, disturbed[law + "#2"][k], color=c, lw=1.6, ls="--", label=f"{law}: disturbed, observer")
            tail(ax, ideal[law][k], color=c, lw=1.2, ls=":", label=f"{law}: no disturbance")
        ax.axvline(tol, color="0.5", lw=1.0)
        ax.set_xscale("log")
        ax.set_xlabel(what)
        ax.set_ylabel("share of runs above x")
        ax.set_yscale("log")
        ax.set_ylim(3e-5, 1.2)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_title("10,000 starts within 2 m, any heading: final distance")
    axes[1].set_title("... and final heading error (grey: the tolerance)")
    handles, labels = axes[0].get_legend_handles_labels()
    # Below the plots: no corner of either is free of data.
    fig.legend(handles, labels, fontsize=7, loc="outside lower center", ncol=4)
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main(*sys.argv[1:4])
