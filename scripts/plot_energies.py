#!/usr/bin/env python3
"""Figure-3-style plot of a rollout: per-frame energy terms on a log scale vs time.
Usage: plot_energies.py ENERGIES.csv OUT.png [--fps 30] [--title T] [ENERGIES2.csv:LABEL ...]
Reads the energies.csv that `pb4u simulate` writes (frame,<term>,...). Extra CSVs given as
PATH:LABEL are overlaid (stretch only), e.g. to compare methods or resolutions. The axis spans
FLOOR of the largest value and up (default 1e-8): a term below it on a frame (a contact term that
is zero where nothing touches) leaves a gap there instead of pulling the axis down to 1e-40."""
import argparse
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


# Columns of energies.csv that are not energies (J): the frame, the residual (mm), and with a
# body the penetration figures, the body's self-crossing and the barrier solve's account.
NOT_ENERGIES = {"frame", "residual_mm", "penetrating_fraction", "max_penetration_mm", "edges_through_body",
                "body_self_crossing_faces", "contact_excluded", "caught_by_body", "body_lag_mm"}


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    cols = {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}
    return cols


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--fps", type=float, default=30.0)
    ap.add_argument("--title", default="")
    ap.add_argument("--floor", type=float, default=1e-8, help="lowest value drawn, as a share of the largest")
    ap.add_argument("overlay", nargs="*")
    a = ap.parse_args()
    cols = read(a.csv)
    if not cols:
        raise SystemExit("%s: no frames" % a.csv)
    t = [f / a.fps for f in cols["frame"]]
    energies = {k: v for k, v in cols.items() if k not in NOT_ENERGIES}
    largest = max((v for vs in energies.values() for v in vs if math.isfinite(v)), default=1.0)
    floor = a.floor * largest if largest > 0 else 0.0
    fig, ax = plt.subplots(figsize=(8, 4))
    for name, values in energies.items():
        positive = [v if v > floor and math.isfinite(v) else float("nan") for v in values]
        style = dict(lw=2.2, color="k") if name == "stretch" else dict(lw=1.0, marker=".", ms=3)
        ax.plot(t, positive, label=name, **style)
    for spec in a.overlay:
        path, _, label = spec.partition(":")
        other = read(path)
        ax.plot([f / a.fps for f in other["frame"]], other["stretch"], "--", label=label or path)
    ax.set_yscale("log")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy per frame (J), log scale")
    if floor > 0:
        ax.set_ylim(bottom=floor)
    ax.set_title(a.title or "Energies of the rollout (stretch in bold; gaps: below %.0e J)" % floor)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(a.png, dpi=120)


if __name__ == "__main__":
    main()
