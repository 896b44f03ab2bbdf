#!/usr/bin/env python3
"""Training curves from one or more runs' metrics.jsonl (SPEC 7): total loss and each
physics term vs step, one panel per key, one line per run.
Usage: plot_metrics.py OUT.png RUN_DIR_OR_JSONL[:LABEL] ... [--smooth 20]
Each panel is a moving median (training samples differ, so a mean follows outliers)."""
import argparse
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SKIP = {"step", "lr", "seconds", "step_seconds", "rollout", "K", "skipped_steps", "collision_weight"}


def load(path):
    if os.path.isdir(path):
        path = os.path.join(path, "metrics.jsonl")
    rows = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line:
                rows.append(json.loads(line))
    return rows


def smooth(values, k):
    """Moving median: samples differ (garment, material, effects), so a mean follows outliers."""
    out, acc = [], []
    for v in values:
        acc.append(v)
        if len(acc) > k:
            acc.pop(0)
        finite = sorted(x for x in acc if x is not None and math.isfinite(x))
        out.append(finite[len(finite) // 2] if finite else float("nan"))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("png")
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--smooth", type=int, default=20)
    a = ap.parse_args()
    runs = []
    for spec in a.runs:
        path, _, label = spec.partition(":")
        runs.append((label or os.path.basename(os.path.normpath(path)), load(path)))
    keys = ["loss"] + sorted({k for _, rows in runs for r in rows for k in r} - SKIP - {"loss"})
    fig, axes = plt.subplots(len(keys), 1, figsize=(7, 2.2 * len(keys)), sharex=True)
    axes = [axes] if len(keys) == 1 else axes
    for ax, key in zip(axes, keys):
        for label, rows in runs:
            pts = [(r["step"], r[key]) for r in rows if key in r and r[key] is not None]
            if pts:
                ax.plot([p[0] for p in pts], smooth([p[1] for p in pts], a.smooth), label=label)
        ax.set_ylabel(key)
        if key not in ("gravity", "loss"):
            ax.set_yscale("log")  # non-negative terms spanning decades
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[-1].set_xlabel("step")
    fig.suptitle("Training curves (moving median over %d steps)" % a.smooth)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
