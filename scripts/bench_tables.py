#!/usr/bin/env python3
"""Print docs/performance.md's three bench tables from a `pb4u bench` run's bench_details.csv.

  /usr/bin/python3 scripts/bench_tables.py runs/bench/blender/bench_details.csv
  /usr/bin/python3 scripts/bench_tables.py --networks runs/bench/baselines/bench_details.csv

- Table 3: latency (median ms), total and positive loss (J per frame) and the share inside the
  body for Pb4U, MGN, the 100-iteration reference solver and Blender's two qualities.
- Equal loss: per network, the fastest reference budget (with a body, not stopped by the
  divergence guard) whose total loss is at or below the network's, its latency and the
  speed-up: the rule of bench's own table.txt (cheapest_at_equal_loss); Blender quality 15
  beside Pb4U.
- Figure 5: the Pb4U weights at fixed K against the resolution-aware K, and the same weights
  with update scaling switched off at inference.
With --networks, one table instead: every network row (configs/bench/baselines.yaml: each model
alone and with the passes) with its latency and positive energy per level, and the growth of
each from the first level to the last (a diverged run's energy is marked).
Methods missing from a run leave "-" in their cells. The networks are found by family and name
prefix, so "Pb4U + projection" (a model file with contact projection) counts as Pb4U.
"""
import csv
import re
import sys


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for key in ("level", "triangles", "K", "iterations"):
            r[key] = int(r[key])
        for key in ("latency_ms_median", "physics_loss", "positive_loss", "penetrating_fraction"):
            r[key] = float(r[key]) if r[key] != "" else 0.0  # no body: no penetration
        r["diverged"] = r["diverged"] == "true"
    return rows


def fmt(x, digits=3):
    if x is None:
        return "-"
    if x != 0 and (abs(x) >= 1e4 or abs(x) < 1e-3):
        return f"{x:.2e}"
    return f"{x:#.{digits}g}".rstrip(".")


def ms(x):
    return "-" if x is None else f"{x:.1f}" if x < 1000 else f"{x:.0f}"


def main(path):
    rows = load(path)
    levels = sorted({r["level"] for r in rows})

    def get(level, method):
        for r in rows:
            if r["level"] == level and r["method"] == method:
                return r
        return None

    def field(r, key):
        return None if r is None else r[key]

    def network(prefix):
        return next((r["method"] for r in rows if r["family"] == "network" and r["method"].startswith(prefix)), prefix)

    pb4u, mgn = network("Pb4U"), network("MGN")

    print("Table 3\n")
    print("| level | triangles | Pb4U K | Pb4U ms | MGN ms | Ref. 100 it ms | Blender q5 ms | Blender q15 ms "
          "| Pb4U total | MGN total | Ref. total | Blender q5 total | Blender q15 total | Pb4U E+ | MGN E+ "
          "| Ref. E+ | Blender q15 E+ | Pb4U inside % | MGN inside % | Blender q15 inside % |")
    print("|" + "---|" * 20)
    for lv in levels:
        p, m, ref = get(lv, pb4u), get(lv, mgn), get(lv, "Reference (100 it)")
        b5, b15 = get(lv, "Blender (quality 5)"), get(lv, "Blender (quality 15)")
        cells = [f"Lv.{lv}", str((p or m or ref)["triangles"]), str(p["K"]) if p else "-"]
        cells += [ms(field(r, "latency_ms_median")) for r in (p, m, ref, b5, b15)]
        cells += [fmt(field(r, "physics_loss"), 4) for r in (p, m, ref, b5, b15)]
        cells += [fmt(field(r, "positive_loss")) for r in (p, m, ref, b15)]
        cells += ["-" if r is None else f"{100 * r['penetrating_fraction']:.2f}" for r in (p, m, b15)]
        print("| " + " | ".join(cells) + " |")

    print("\nEqual loss\n")
    print("| level | network | its loss J | cheapest reference budget at or below it | its ms | speed-up "
          "| best Blender (q15) loss J / ms |")
    print("|---|---|---|---|---|---|---|")
    budget = re.compile(r"^Reference \((\d+) it\)$")
    for lv in levels:
        refs = sorted(((r["latency_ms_median"], int(budget.match(r["method"]).group(1)), r) for r in rows
                       if r["level"] == lv and budget.match(r["method"]) and not r["diverged"]),
                      key=lambda t: t[0])
        for name in (pb4u, mgn):
            net = get(lv, name)
            if net is None:
                continue
            match = next(((it, r) for _, it, r in refs if r["physics_loss"] <= net["physics_loss"]), None)
            cells = [f"Lv.{lv}", name, fmt(net["physics_loss"], 4)]
            if match:
                it, r = match
                cells += [f"{it} it ({fmt(r['physics_loss'], 4)} J)", ms(r["latency_ms_median"]),
                          f"{r['latency_ms_median'] / net['latency_ms_median']:.1f}x"]
            else:
                cells += ["none", "-", "-"]
            b15 = get(lv, "Blender (quality 15)")
            cells.append(f"{fmt(b15['physics_loss'])} / {ms(b15['latency_ms_median'])}" if b15 and name == pb4u else "")
            print("| " + " | ".join(cells) + " |")

    print("\nFigure 5\n")
    print("| level | own K | own total J | best fixed K | its total J | own / best | E+ at K = 0 | own E+ "
          "| E+ at best K | E+ w/o update scaling |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for lv in levels:
        own = get(lv, pb4u)
        fixed = [r for r in rows if r["level"] == lv and r["family"] == "fixed_k"]
        if own is None or not fixed:
            continue
        best = min(fixed, key=lambda r: r["physics_loss"])
        k0 = next((r for r in fixed if r["K"] == 0), None)
        no_us = next((r for r in rows if r["level"] == lv and r["family"] == "ablation" and "w/o US" in r["method"]),
                     None)
        print("| " + " | ".join([
            f"Lv.{lv}", str(own["K"]), fmt(own["physics_loss"], 4), str(best["K"]), fmt(best["physics_loss"], 4),
            f"{own['physics_loss'] / best['physics_loss']:.2f}", fmt(field(k0, "positive_loss")),
            fmt(own["positive_loss"]), fmt(best["positive_loss"]), fmt(field(no_us, "positive_loss"), 4)]) + " |")


def networks(path):
    rows = load(path)
    levels = sorted({r["level"] for r in rows})
    names = []
    for r in rows:
        if r["family"] == "network" and r["method"] not in names:
            names.append(r["method"])
    by = {(r["level"], r["method"]): r for r in rows if r["family"] == "network"}
    tri = {lv: next(r["triangles"] for r in rows if r["level"] == lv) for lv in levels}
    print("Latency (median ms per step) and positive energy (J per frame), per level\n")
    head = ["method"] + [f"Lv.{lv} ({tri[lv]} tri) ms" for lv in levels] + [f"ms Lv.{levels[-1]} / Lv.{levels[0]}"]
    head += [f"Lv.{lv} E+" for lv in levels] + [f"E+ Lv.{levels[-1]} / Lv.{levels[0]}"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for name in names:
        cells = [name]
        lat = [field(by.get((lv, name)), "latency_ms_median") for lv in levels]
        cells += [ms(x) for x in lat]
        cells.append(f"{lat[-1] / lat[0]:.2f}x" if lat[0] and lat[-1] else "-")
        energy = []
        for lv in levels:
            r = by.get((lv, name))
            energy.append(None if r is None else r["positive_loss"])
            mark = " (diverged)" if r is not None and r["diverged"] else ""
            cells.append(fmt(energy[-1]) + mark)
        cells.append(f"{energy[-1] / energy[0]:.2f}x" if energy[0] and energy[-1] else "-")
        print("| " + " | ".join(cells) + " |")


def field(r, key):
    return None if r is None else r[key]


if __name__ == "__main__":
    args = sys.argv[1:]
    if len(args) == 2 and args[0] == "--networks":
        networks(args[1])
        sys.exit(0)
    if len(args) != 1 or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        sys.exit(0 if len(args) == 1 else 2)
    main(args[0])
