#!/usr/bin/env python3
"""Figures of a `pb4u bench` run, from DIR/bench_details.csv:
  loss_vs_k.png           positive energy vs K of the fixed-K Pb4U runs, one line per level (Figure 5);
                          the K that Pb4U picks by itself is starred
  loss_vs_latency.png     physics loss vs per-frame latency, one panel per level (the Pareto view)
  latency_vs_vertices.png latency vs vertex count, log-log, with each method's fitted exponent
Usage: plot_bench.py DIR"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("level", "triangles", "vertices", "K", "iterations", "threads"):
            r[k] = int(r[k])
        for k in ("latency_ms_median", "latency_ms_min", "physics_loss", "positive_loss"):
            r[k] = float(r[k])
    return rows


def finite(v):
    return math.isfinite(v)


def level_label(rows, level):
    r = next(r for r in rows if r["level"] == level)
    return f"Lv.{level} ({r['triangles']} tri)"


def set_loss_scale(ax, values):
    if values and min(values) > 0:
        ax.set_yscale("log")
    else:
        ax.set_yscale("symlog", linthresh=1e-2)


def loss_vs_k(rows, levels, out):
    # The positive energy (stretch + bending + collision), as in loss_vs_latency: the total is
    # gravity's ~1 J a frame at every K.
    y = "positive_loss"
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    values = []
    for level in levels:
        pts = sorted((r["K"], r[y]) for r in rows
                     if r["level"] == level and r["family"] == "fixed_k" and finite(r[y]))
        if not pts:
            continue
        line, = ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", ms=4, label=level_label(rows, level))
        values += [p[1] for p in pts]
        own = [r for r in rows if r["level"] == level and r["family"] == "network" and r["K"] > 0
               and finite(r[y])]
        if own:
            ax.plot([own[0]["K"]], [own[0][y]], "*", ms=13, color=line.get_color(), mec="k")
    set_loss_scale(ax, values)
    ax.set_xlabel("propagation steps K")
    ax.set_ylabel("positive energy per frame (J)")
    ax.set_title("Positive energy vs K (star: K = floor(D / mean edge length))")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=130)


def loss_vs_latency(rows, levels, out):
    # The positive energy (stretch + bending + collision), not the total: gravity's ~1 J a frame
    # is the same for every method and would hide what separates them.
    y = "positive_loss"
    fig, axes = plt.subplots(1, len(levels), figsize=(4.2 * len(levels), 5.0), squeeze=False)
    palette = list(plt.get_cmap("tab10").colors) + list(plt.get_cmap("Dark2").colors)
    network_bases = list(dict.fromkeys(r["method"].split(" + ")[0] for r in rows
                                       if r["family"] in ("network", "ablation")))
    for ax, level in zip(axes[0], levels):
        here = [r for r in rows if r["level"] == level and r["family"] != "no_body"
                and finite(r[y]) and r[y] > 0 and finite(r["latency_ms_median"])]
        # The axis ends 10x above the highest network row that ran to the end (alone, with passes or
        # refined): a solver budget far above it (1e5 J) would squeeze what separates the methods
        # into a sliver. Rows above the top are drawn on it as open triangles with their value.
        ours = [r[y] for r in here if r["family"] in ("network", "ablation", "refined", "refined_tolerance")
                and r.get("diverged") != "true"]
        top = 10 * max(ours) if ours else None

        def shown(v):
            return v if top is None or v <= top else top

        def mark_clipped(r, color):
            if top is not None and r[y] > top:
                ax.plot([r["latency_ms_median"]], [top], "^", ms=7, mfc="none", color=color, clip_on=False)
        # One curve per family and, for the refined rows, per network ("MGN + 5 it" -> MGN).
        curves = [("reference", None, "s-", "0.4", "reference solver, penalty contact", "{} it"),
                  ("reference_barrier", None, "v-", "tab:purple", "reference solver, intersection-free", "{} it"),
                  ("blender", None, "^-", "black", "Blender cloth", "q{}")]
        refined_colors = ["tab:green", "tab:red", "tab:brown", "tab:olive"]
        for name in dict.fromkeys(r["method"].rsplit(" + ", 1)[0] for r in here if r["family"] == "refined"):
            curves.append(("refined", name, "D-", refined_colors[len(curves) % len(refined_colors)],
                           name + " + solver iterations", "+{}"))
        for family, base, style, color, label, note in curves:
            pts = sorted((r for r in here if r["family"] == family
                          and (base is None or r["method"].rsplit(" + ", 1)[0] == base)),
                         key=lambda r: r["iterations"])
            if not pts:
                continue
            ax.plot([r["latency_ms_median"] for r in pts], [shown(r[y]) for r in pts], style, color=color,
                    label=label, ms=5)
            for r in pts:
                mark_clipped(r, color)
                text = note.format(r["iterations"]) + (" div." if r.get("diverged") == "true" else "")
                if top is not None and r[y] > top:  # off the top: its label hangs below the triangle
                    ax.annotate(text, (r["latency_ms_median"], top), fontsize=6, xytext=(0, -5),
                                textcoords="offset points", rotation=90, ha="center", va="top", color=color)
                else:
                    ax.annotate(text, (r["latency_ms_median"], r[y]), fontsize=6.5, xytext=(3, 3),
                                textcoords="offset points")
        # The converged reference (its largest budget that ran to the end): what the others approach.
        converged = [r for r in here if r["family"] == "reference_barrier" and r.get("diverged") != "true"]
        if converged:
            c = max(converged, key=lambda r: r["iterations"])
            ax.axhline(c[y], ls="--", lw=0.8, color="tab:purple", alpha=0.6,
                       label="reference solver, intersection-free, largest budget")
        # A network refined until the solver's step is below a tolerance: a star per tolerance.
        for r in (r for r in here if r["family"] == "refined_tolerance"):
            tolerance = r["method"].rsplit(" + ", 1)[1]
            ax.plot([r["latency_ms_median"]], [r[y]], "*", ms=10, color="tab:cyan",
                    label="network + solver to a tolerance")
            ax.annotate(tolerance, (r["latency_ms_median"], r[y]), fontsize=7,
                        xytext=(3, -9), textcoords="offset points")
        fk = sorted((r for r in here if r["family"] == "fixed_k"), key=lambda r: r["K"])
        if fk:
            ax.plot([r["latency_ms_median"] for r in fk], [shown(r[y]) for r in fk], ".:",
                    color="tab:blue", alpha=0.6, label="Pb4U, fixed K")
        # A network's colour is its method's at every level; with passes ("X + ...") a square.
        for r in here:
            if r["family"] in ("network", "ablation"):
                base = r["method"].split(" + ")[0]
                marker = "x" if r["family"] == "ablation" else ("s" if base != r["method"] else "o")
                color = palette[network_bases.index(base) % len(palette)]
                ax.plot([r["latency_ms_median"]], [shown(r[y])], marker, ms=8, label=r["method"], color=color)
                mark_clipped(r, color)
        ax.set_xscale("log")
        ax.set_yscale("log")
        if top is not None:
            ax.set_ylim(top=top)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # no crowded minor labels
        ax.set_title(level_label(rows, level), fontsize=9)
        ax.set_xlabel("latency per frame (ms)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("positive energy per frame (J)")
    # One legend for every panel, below them, clear of the data.
    handles, labels = {}, []
    for ax in axes[0]:
        for h, l in zip(*ax.get_legend_handles_labels()):
            if l not in handles:
                handles[l] = h
                labels.append(l)
    ncol = min(3, len(labels))
    fig.legend([handles[l] for l in labels], labels, loc="lower center", ncol=ncol, fontsize=7)
    fig.suptitle("Accuracy vs time: positive energy (stretch + bending + collision), lower left is better\n"
                 "open triangles: runs far above every network's energy, drawn on the top edge; div.: diverged",
                 fontsize=10)
    rows_of_labels = (len(labels) + ncol - 1) // max(ncol, 1)
    fig.tight_layout(rect=(0, 0.02 + 0.045 * rows_of_labels, 1, 1))
    fig.savefig(out, dpi=130)


def latency_vs_vertices(rows, out):
    fig, ax = plt.subplots(figsize=(9.6, 4.4))
    methods = []
    for r in rows:
        if r["family"] != "fixed_k" and r["method"] not in methods:
            methods.append(r["method"])
    # One colour per method, its passes or refinement ("X + ...") dashed in the same colour.
    palette = list(plt.get_cmap("tab10").colors) + list(plt.get_cmap("Dark2").colors)
    bases = list(dict.fromkeys(m.split(" + ")[0] for m in methods))
    for m in methods:
        pts = sorted((r["vertices"], r["latency_ms_median"]) for r in rows
                     if r["method"] == m and finite(r["latency_ms_median"]) and r["latency_ms_median"] > 0)
        if len(pts) < 2:
            continue
        xs = [math.log(p[0]) for p in pts]
        ys = [math.log(p[1]) for p in pts]
        mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
        sxx = sum((x - mx) ** 2 for x in xs)
        slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")
        base = m.split(" + ")[0]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o--" if base != m else "o-", ms=4,
                color=palette[bases.index(base) % len(palette)], label=f"{m}  (exponent {slope:.2f})")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("garment vertices")
    ax.set_ylabel("latency per frame (ms)")
    ax.set_title("Latency vs resolution (log-log, fitted exponent)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))  # beside the axes, clear of the data
    fig.tight_layout()
    fig.savefig(out, dpi=130)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    d = sys.argv[1]
    rows = read(os.path.join(d, "bench_details.csv"))
    if not rows:
        sys.exit("plot_bench.py: no rows in bench_details.csv")
    levels = sorted({r["level"] for r in rows})
    loss_vs_k(rows, levels, os.path.join(d, "loss_vs_k.png"))
    loss_vs_latency(rows, levels, os.path.join(d, "loss_vs_latency.png"))
    latency_vs_vertices(rows, os.path.join(d, "latency_vs_vertices.png"))


if __name__ == "__main__":
    main()
