#!/usr/bin/env python3
"""The ranking table of scripts/rank_models.sh: each run's mean and spread over its checkpoints.

Usage: rank_table.py RUN:MEMBER:VARIANT:DIR ... [--reference DIR] [--json FILE]

DIR holds one model file's probes: step.json, unseen.json and skirt.json (pb4u evaluate --format json),
walk/ and hang/ (pb4u simulate: energies.csv, requested_frames). Standard library only.
"""
import csv
import json
import math
import sys

POSITIVE = ("stretch", "bending", "collision")
# The probe columns, in order: key, header, how a cell is printed.
COLUMNS = [
    ("step_stretch", "one step: stretch J", "{:.4f}"),
    ("step_collision", "one step: collision J", "{:.4f}"),
    ("walk", "walk: E+ J", "{:.4f}"),
    ("walk_inside", "walk: inside max %", "{:.2f}"),
    ("hang", "hang: E+ J", "{:.4f}"),
    ("unseen_1", "run_1 Lv.1: E+ J", "{:.4f}"),
    ("unseen_1_inside", "run_1 Lv.1: inside max %", "{:.2f}"),
    ("unseen_finest", "run_1 finest: E+ J", "{:.4f}"),
    ("skirt", "skirt run_1 Lv.1: E+ J", "{:.4f}"),
    ("score", "score", "{:.4f}"),
]
# The probes whose positive energies make the score (geometric mean).
SCORED = ("step", "walk", "hang", "unseen_1", "unseen_finest", "skirt")


def only_method(level):
    methods = level["methods"]
    if len(methods) != 1:
        raise SystemExit("rank_table.py: expected one method per file, got %s" % list(methods))
    return next(iter(methods.values()))


def read_simulation(path):
    """Positive energy per frame (mean), largest inside share (%), and whether it stopped early."""
    with open(path + "/requested_frames") as f:
        requested = int(f.read())
    try:
        rows = list(csv.DictReader(open(path + "/energies.csv")))
    except FileNotFoundError:
        return {"energy": math.nan, "inside": math.nan, "diverged": True}
    energies, inside = [], []
    for row in rows:
        if int(row["frame"]) == 0:
            continue
        e = sum(float(row[k]) for k in POSITIVE if k in row)
        if not math.isfinite(e):
            break
        energies.append(e)
        if row.get("penetrating_fraction", "") not in ("", "nan"):
            inside.append(100 * float(row["penetrating_fraction"]))
    return {
        "energy": sum(energies) / len(energies) if energies else math.nan,
        "inside": max(inside) if inside else math.nan,
        "diverged": len(energies) < requested,
    }


def read_probes(directory, reference=False):
    out = {"diverged": []}
    step = only_method(json.load(open(directory + "/step.json"))["levels"][0])
    out["step_stretch"] = step["stretch"]
    out["step_collision"] = step["collision"]
    out["step"] = step["stretch"] + step["collision"]
    if step.get("diverged"):
        out["diverged"].append("one step")
    for name in ("walk", "hang"):
        sim = read_simulation(directory + "/" + name)
        out[name] = sim["energy"]
        if name == "walk":
            out["walk_inside"] = sim["inside"]
        if sim["diverged"]:
            out["diverged"].append(name)
    levels = json.load(open(directory + "/unseen.json"))["levels"]
    for i, level in enumerate(levels):
        m = only_method(level)
        key = "unseen_1" if i == 0 else "unseen_finest"
        out[key] = sum(m.get(k, 0.0) for k in POSITIVE)
        if i == 0:
            out["unseen_1_inside"] = 100 * m.get("max_penetrating_fraction", math.nan)
        if m.get("diverged"):
            out["diverged"].append("run_1 Lv.%d" % level["level"])
    skirt = only_method(json.load(open(directory + "/skirt.json"))["levels"][0])
    out["skirt"] = sum(skirt.get(k, 0.0) for k in POSITIVE)
    if skirt.get("diverged"):
        out["diverged"].append("skirt")
    scored = [out.get(k, math.nan) for k in SCORED if not (reference and k == "unseen_finest")]
    finite = all(math.isfinite(v) and v > 0 for v in scored)
    out["score"] = math.exp(sum(math.log(v) for v in scored) / len(scored)) if finite else math.nan
    if out["diverged"]:
        out["score"] = math.inf
    return out


def cell(values, fmt):
    values = [v for v in values if v is not None]
    if not values:
        return "-"
    if any(v == math.inf for v in values):
        return "diverged"
    if any(not math.isfinite(v) for v in values):
        return "n/a"
    mean = sum(values) / len(values)
    if len(values) == 1:
        return fmt.format(mean)
    return (fmt + " ({}-{})").format(mean, fmt.format(min(values)), fmt.format(max(values)))


def main(argv):
    members, reference, json_out = [], None, None
    i = 0
    while i < len(argv):
        if argv[i] == "--reference":
            reference = argv[i + 1]
            i += 2
        elif argv[i] == "--json":
            json_out = argv[i + 1]
            i += 2
        else:
            run, member, variant, directory = argv[i].split(":", 3)
            members.append((run, member, variant, directory))
            i += 1
    results = {}
    for run, member, variant, directory in members:
        results.setdefault((run, variant), []).append(read_probes(directory))
    ref = read_probes(reference, reference=True) if reference else None

    header = ["run", "variant", "checkpoints"] + [c[1] for c in COLUMNS] + ["diverged"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    # Rank by the mean score of the network alone, then with the passes.
    def mean_score(key):
        s = [r["score"] for r in results[key]]
        return sum(s) / len(s) if all(math.isfinite(v) for v in s) else math.inf

    order = sorted(results, key=lambda k: (k[1] != "alone", mean_score(k)))
    for key in order:
        rows = results[key]
        diverged = sorted({d for r in rows for d in r["diverged"]})
        cells = [key[0], "network alone" if key[1] == "alone" else "+ projection + strain limit", str(len(rows))]
        cells += [cell([r.get(c[0]) for r in rows], c[2]) for c in COLUMNS]
        cells.append(", ".join(diverged) if diverged else "none")
        lines.append("| " + " | ".join(cells) + " |")
    if ref:
        cells = ["reference solver", "-", "-"]
        cells += [cell([ref.get(c[0])], c[2]) if c[0] not in ("unseen_finest", "score") else "-" for c in COLUMNS]
        cells.append(", ".join(ref["diverged"]) or "none")
        lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
        lines.append("Each run's mean over its checkpoints as a multiple of the reference solver:")
        lines.append("")
        ratio_columns = [c for c in COLUMNS if c[0] in ("step_stretch", "step_collision", "walk", "hang", "unseen_1", "skirt")]
        lines.append("| run | variant | " + " | ".join(c[1] for c in ratio_columns) + " |")
        lines.append("|---|---|" + "---|" * len(ratio_columns))
        for key in order:
            rows = results[key]
            cells = [key[0], key[1]]
            for c in ratio_columns:
                values = [r.get(c[0], math.nan) for r in rows]
                mean = sum(values) / len(values)
                r = ref.get(c[0], math.nan)
                cells.append("%.2fx" % (mean / r) if math.isfinite(mean) and r > 0 else "n/a")
            lines.append("| " + " | ".join(cells) + " |")
    print("\n".join(lines))
    if json_out:
        dump = {"runs": [{"run": k[0], "variant": k[1], "members": v} for k, v in results.items()]}
        if ref:
            dump["reference"] = ref
        with open(json_out, "w") as f:
            json.dump(dump, f, indent=1, default=lambda x: None)


if __name__ == "__main__":
    main(sys.argv[1:])
