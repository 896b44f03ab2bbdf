#!/usr/bin/env python3
"""Markdown stability table from `pb4u evaluate --format json` runs (issue 14, SPEC 9).
Usage: stability_table.py RUN.json[,MORE.json ...]:LABEL [...] [--reference NAME | --no-reference] [--note TEXT]
Each run holds the networks and the reference solver on the same sequences (evaluate's
per-method "sequences" list); a run given as several comma-separated files (say the networks'
and a cached solver run of the same config) is their methods merged level by level.
Per sequence (garment, motion, body), level and network: its
positive energy (stretch + bending + collision) as a ratio to the solver's on the same sequence
(mean per frame, and largest frame), the share of garment vertices inside the body (mean and
largest over frames), the deepest penetration (mm), the cloth edges through the body (most on a
frame, share of frames with any), and where it diverged. With --no-reference
(runs of the networks alone, e.g. every held-out motion, where the solver would take hours):
the energies in J instead of ratios, and how many rollouts diverged. Standard library only."""
import argparse
import json
import math
import statistics
import sys


def ratio(a, b):
    if a is None or b is None or not math.isfinite(a) or not math.isfinite(b):
        return "n/a"
    if b <= 0:
        return "n/a (solver 0 J)"
    return "%.3g" % (a / b)


def percent(v):
    return "-" if v is None else "%.2f" % (100 * v)


def mm(v):
    return "-" if v is None else "%.2f" % v


def diverged(q):
    if not q.get("diverged"):
        return "no"
    reason = q.get("diverged_reason", "")
    return "frame %s%s" % (q.get("diverged_at_frame"), " (%s)" % reason if reason else "")


def case_name(q):
    """garment / motion / body; a body-less sequence is the garment as fitted to that body, hanging."""
    if q["motion"] == "rest":
        return "%s (%s's) / hanging from rest / no body" % (q["garment"], q["body"])
    return "%s / %s / %s" % (q["garment"], q["motion"], q["body"])


def load_run(paths):
    """One evaluate run from one or more JSON files: the methods of equal levels merged."""
    merged = None
    for path in paths:
        with open(path) as f:
            run = json.load(f)
        if merged is None:
            merged = run
            continue
        levels = {lv["level"]: lv for lv in merged["levels"]}
        for lv in run["levels"]:
            if lv["level"] not in levels:
                sys.exit("stability_table.py: %s has level %s, which %s lacks" % (path, lv["level"], paths[0]))
            levels[lv["level"]]["methods"].update(lv["methods"])
    return merged


def rows_of(run, label, reference):
    """Yields one table row (a list of cells) per network, sequence and level, and per-network
    worst figures for the summary."""
    out, summary = [], {}
    for level in run["levels"]:
        methods = level["methods"]
        if reference not in methods:
            sys.exit("stability_table.py: no method '%s' in level %s (run evaluate with --method reference)"
                     % (reference, level["level"]))
        solver = {(q["body"], q["garment"], q["motion"]): q for q in methods[reference]["sequences"]}
        for name, m in methods.items():
            if name == reference:
                continue
            s = summary.setdefault(name, {"cases": 0, "diverged": 0, "mean_ratio": 0.0, "max_ratio": 0.0,
                                          "inside": None, "depth": None, "mean_ratios": []})
            for q in m["sequences"]:
                key = (q["body"], q["garment"], q["motion"])
                ref = solver.get(key)
                if ref is None:
                    continue
                case = case_name(q)
                mean_r = ratio(q.get("positive_energy"), ref.get("positive_energy"))
                max_r = ratio(q.get("max_positive_energy"), ref.get("max_positive_energy"))
                out.append([label, case, str(level["level"]), name, "%d / %d" % (q["frames"], ref["frames"]), mean_r,
                            max_r, percent(q.get("penetrating_fraction")), percent(q.get("max_penetrating_fraction")),
                            mm(q.get("max_penetration_mm")), mm(ref.get("max_penetration_mm"))] + edges(q) +
                           [edges(ref)[0], crossing(ref), diverged(q), diverged(ref)])
                s["cases"] += 1
                s["diverged"] += bool(q.get("diverged"))
                for k, v in (("mean_ratio", mean_r), ("max_ratio", max_r)):
                    try:
                        s[k] = max(s[k], float(v))
                    except ValueError:
                        pass
                try:
                    s["mean_ratios"].append(float(mean_r))
                except ValueError:
                    pass
                for k, key in (("inside", "max_penetrating_fraction"), ("depth", "max_penetration_mm"),
                               ("edges", "max_edges_through")):
                    if q.get(key) is not None and q[key] >= 0:
                        s[k] = max(s.get(k) or 0.0, q[key])
    return out, summary


def rows_without_reference(run, label):
    """Networks alone: one row per network, sequence and level (energies in J), and per-network
    summaries."""
    out, summary = [], {}
    for level in run["levels"]:
        for name, m in level["methods"].items():
            s = summary.setdefault(name, {"cases": 0, "diverged": 0, "means": [], "inside": None, "depth": None,
                                          "stopped": []})
            for q in m["sequences"]:
                case = case_name(q)
                e, emax = q.get("positive_energy"), q.get("max_positive_energy")
                out.append([label, case, str(level["level"]), name, str(q["frames"]),
                            "%.3g" % e if e is not None else "n/a", "%.3g" % emax if emax is not None else "n/a",
                            percent(q.get("penetrating_fraction")), percent(q.get("max_penetrating_fraction")),
                            mm(q.get("max_penetration_mm"))] + edges(q) + [crossing(q), diverged(q)])
                s["cases"] += 1
                if q.get("diverged"):
                    s["diverged"] += 1
                    s["stopped"].append("%s / %s (%s)" % (q["garment"], q["motion"], q.get("diverged_at_frame")))
                if e is not None and math.isfinite(e):
                    s["means"].append(e)
                for k, key in (("inside", "max_penetrating_fraction"), ("depth", "max_penetration_mm"),
                               ("edges", "max_edges_through")):
                    if q.get(key) is not None and q[key] >= 0:
                        s[k] = max(s.get(k) or 0.0, q[key])
    return out, summary


def most_edges(v):
    return "%d" % v["edges"] if v.get("edges") is not None else "n/a"


def print_without_reference(specs, note):
    rows, summaries = [], {}
    for spec in specs:
        path, _, label = spec.rpartition(":") if ":" in spec else (spec, "", spec)
        r, s = rows_without_reference(load_run(path.split(",")), label or path)
        rows += r
        for name, v in s.items():
            summaries[(label, name)] = v
    print("# Held-out stability: the networks alone\n")
    if note:
        print(note + "\n")
    print("No reference solver: E+ = positive energy (stretch + bending + collision) in J per frame, mean over the "
          "frames run and largest frame. Inside: share of garment vertices inside the body (mean / largest over "
          "frames); depth: deepest penetration; edges thru: cloth edges through a body triangle (most on a frame, "
          "share of frames with any); body crosses itself: share of the frames run on which one part of the body lies "
          "inside another. Diverged: stopped by the guard at that frame.\n")
    print(table(["run", "case (garment / motion / body)", "level", "network", "frames", "E+ mean J", "E+ max J",
                 "inside mean %", "inside max %", "depth max mm", "edges thru max", "edges thru frames %",
                 "body crosses itself frames %", "diverged"], rows))
    print("\n## Per network\n")
    print(table(["run", "network", "cases", "diverged", "median E+ mean J", "worst inside %", "deepest mm",
                 "most edges thru", "stopped (garment / motion (frame))"],
                [[label, name, str(v["cases"]), str(v["diverged"]), median(v["means"]), percent(v["inside"]),
                  mm(v["depth"]), most_edges(v), "; ".join(v["stopped"]) or "-"] for (label, name), v in summaries.items()]))


def edges(q):
    """The most cloth edges through the body on a frame, and the share of frames with any: 'n/a'
    for runs made before evaluate counted them."""
    most, frames = q.get("max_edges_through"), q.get("edges_through_frames")
    if most is None or most < 0:
        return ["n/a", "n/a"]
    return ["%d" % most, percent(frames) if frames is not None else "n/a"]


def crossing(q):
    """The share of frames on which the body crosses itself (one part inside another, where
    pinched cloth has no free place): 'n/a' for runs made before evaluate measured it."""
    frames = q.get("body_self_crossing_frames")
    return percent(frames) if frames is not None else "n/a"


def median(values):
    return "%.3g" % statistics.median(values) if values else "n/a"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", help="RUN.json:LABEL")
    ap.add_argument("--reference", default="Reference", help="the solver's method name in the runs")
    ap.add_argument("--no-reference", action="store_true",
                    help="the runs hold networks only: energies in J, divergence counts, no ratios")
    ap.add_argument("--note", default="", help="a line printed under the title (frames, threads, machine)")
    a = ap.parse_args()
    if a.no_reference:
        return print_without_reference(a.runs, a.note)
    rows, summaries = [], {}
    for spec in a.runs:
        path, _, label = spec.rpartition(":") if ":" in spec else (spec, "", spec)
        run = load_run(path.split(","))
        r, s = rows_of(run, label or path, a.reference)
        rows += r
        for name, v in s.items():
            summaries[(label, name)] = v
    print("# Held-out stability: networks against the reference solver\n")
    if a.note:
        print(a.note + "\n")
    print("E+ = positive energy (stretch + bending + collision, J per frame); ratios are the network's over the "
          "solver's on the same sequence (mean over each one's measured frames, and largest frame). Inside: share "
          "of garment vertices inside the body (mean / largest over frames); depth: deepest penetration; edges "
          "thru: cloth edges through a body triangle (most on a frame, share of frames with any). Body crosses "
          "itself: share of the solver's frames on which one part of the body lies inside another, where cloth "
          "pinched between them has no free place for any method. Frames: measured by the network / by the "
          "solver.\n")
    print(table(["run", "case (garment / motion / body)", "level", "network", "frames", "E+ mean ratio",
                 "E+ max ratio", "inside mean %", "inside max %", "depth max mm", "solver depth max mm",
                 "edges thru max", "edges thru frames %", "solver edges thru max", "body crosses itself frames %",
                 "diverged", "solver diverged"],
                rows))
    print("\n## Worst case per network\n")
    print(table(["run", "network", "cases", "diverged", "median E+ mean ratio", "worst E+ mean ratio",
                 "worst E+ max ratio", "worst inside %", "deepest mm", "most edges thru"],
                [[label, name, str(v["cases"]), str(v["diverged"]), median(v["mean_ratios"]), "%.3g" % v["mean_ratio"],
                  "%.3g" % v["max_ratio"], percent(v["inside"]), mm(v["depth"]), most_edges(v)]
                 for (label, name), v in summaries.items()]))


if __name__ == "__main__":
    main()
