#!/usr/bin/env python3
"""Figure-3-style plot of a rollout: per-frame energy terms on a log scale vs time.
Usage: plot_energies.py ENERGIES.csv OUT.png [--fps 30] [--title T] [ENERGIES2.csv:LABEL ...]
Reads the energies.csv that `pb4u simulate` writes (frame,<term>,...). Extra CSVs given as
PATH:LABEL are overlaid (stretch only), e.g. to compare methods or resolutions."""
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
    ap.add_argument("overlay", nargs="*")
    a = ap.parse_args()
    cols = read(a.csv)
    if not cols:
        raise SystemExit("%s: no frames" % a.csv)
    t = [f / a.fps for f in cols["frame"]]
    fig, ax = plt.subplots(figsize=(7, 4))
    for name, values in cols.items():
        if name in NOT_ENERGIES:
            continue
        positive = [v if v > 0 and math.isfinite(v) else float("nan") for v in values]
        style = dict(lw=2.2, color="k") if name == "stretch" else dict(lw=1.0)
        ax.plot(t, positive, label=name, **style)
    for spec in a.overlay:
        path, _, label = spec.partition(":")
        other = read(path)
        ax.plot([f / a.fps for f in other["frame"]], other["stretch"], "--", label=label or path)
    ax.set_yscale("log")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy per frame (J), log scale")
    ax.set_title(a.title or "Energies of the rollout (stretch in bold)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.png, dpi=120)


if __name__ == "__main__":
    main()
