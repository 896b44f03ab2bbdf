#!/usr/bin/env python3
"""Table 1 across methods from `pb4u evaluate --format json`: per method and level the mean
positive energy (stretch + bending + collision, J per frame) and its terms, the share of garment
vertices inside the body, the deepest penetration and the diverged sequences; then each
method's growth of the positive energy from the first level to the last (the paper's question:
does a method trained on the coarsest level stay put on finer ones?). With a method named
"Reference" among them, a last table puts each method's positive energy beside its ratio to the
reference's on the same level, with the most vertices inside the body on a frame (%), the most
cloth edges through it on a frame and the median time of a step (ms, where evaluate wrote it).

  /usr/bin/python3 scripts/table1_growth.py runs/table1/quick.json [more.json ...]

Several files (the same levels and sequences, other methods) are merged. A level's value of a
method with a diverged sequence averages the frames measured, as evaluate does, and is marked.
"""
import json
import sys


def fmt(x):
    if x is None:
        return "-"
    if x != 0 and (abs(x) >= 1e3 or abs(x) < 1e-3):
        return f"{x:.2e}"
    return f"{x:.4g}"


def main(paths):
    levels = {}
    order = []
    for path in paths:
        with open(path) as f:
            for lv in json.load(f)["levels"]:
                entry = levels.setdefault(lv["level"], {"triangles": lv["triangles"], "methods": {}})
                for name, m in lv["methods"].items():
                    entry["methods"][name] = m
                    if name not in order:
                        order.append(name)
    lvs = sorted(levels)
    print("| method | level | triangles | stretch | bending | collision | E+ | inside % | deepest mm | diverged |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    growth = {}
    for name in order:
        for lv in lvs:
            m = levels[lv]["methods"].get(name)
            if m is None:
                continue
            positive = m["stretch"] + m["bending"] + m["collision"]
            diverged = [s for s in m.get("sequences", []) if s.get("diverged")]
            where = ", ".join(f"{s['garment']} at {s['diverged_at_frame']}" for s in diverged)
            growth.setdefault(name, {})[lv] = (positive, bool(diverged))
            print("| " + " | ".join([
                name, f"Lv.{lv}", str(levels[lv]["triangles"]), fmt(m["stretch"]), fmt(m["bending"]),
                fmt(m["collision"]), fmt(positive), f"{100 * m.get('penetrating_fraction', 0):.2f}",
                f"{m.get('max_penetration_mm', 0):.1f}", where or "none"]) + " |")
    print()
    print(f"| method | E+ Lv.{lvs[0]} | E+ Lv.{lvs[-1]} | growth Lv.{lvs[-1]} / Lv.{lvs[0]} |")
    print("|---|---|---|---|")
    for name in order:
        g = growth.get(name, {})
        if lvs[0] not in g or lvs[-1] not in g:
            continue
        (a, da), (b, db) = g[lvs[0]], g[lvs[-1]]
        mark = " (diverged)" if da or db else ""
        print(f"| {name} | {fmt(a)} | {fmt(b)} | {b / a:.2f}x{mark} |")

    reference = "Reference"
    if not all(reference in levels[lv]["methods"] for lv in lvs):
        return
    print()
    print("| method | " + " | ".join(f"Lv.{lv}" for lv in lvs) + " |")
    print("|---|" + "---|" * len(lvs))
    for name in [reference] + [n for n in order if n != reference]:
        cells = []
        for lv in lvs:
            m = levels[lv]["methods"].get(name)
            if m is None:
                cells.append("-")
                continue
            positive, diverged = growth[name][lv]
            ref = growth[reference][lv][0]
            cell = fmt(positive) if name == reference else f"{fmt(positive)} ({positive / ref:.3g}x)"
            if diverged:
                cell += ", diverged"
            if "max_penetrating_fraction" in m:
                cell += f"; {100 * m['max_penetrating_fraction']:.2f}%, {int(m.get('max_edges_through', 0))}"
            if m.get("step_ms") is not None:
                cell += f"; {m['step_ms']:.4g} ms"
            cells.append(cell)
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        sys.exit(0 if len(sys.argv) == 2 else 2)
    main(sys.argv[1:])
