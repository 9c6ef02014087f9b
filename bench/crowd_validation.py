#!/usr/bin/env python3
"""The crowd's validation figures (docs/crowd-validation.md): the fundamental diagram in the periodic
corridor (bench program fundamental_diagram) and the flow through bottlenecks of several widths
(scenarios/verification/bottleneck_1m.json, widened, run by `hrisim run`), each beside the
literature, printed as Markdown tables and drawn as SVG plots (standard library only).

usage: python3 bench/crowd_validation.py BUILD_DIR [--seeds N] [--svg-dir docs]
  BUILD_DIR holds server/app/hrisim and bench/fundamental_diagram (a build with HRISIM_BUILD_BENCH).
"""
import argparse
import copy
import json
import math
import os
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)
WIDTHS = [0.8, 1.0, 1.2, 1.4, 1.6, 2.0]  # m, the bottleneck's clear width
# Specific flow through bottlenecks as the issue collects the literature (Seyfried et al. 2009,
# Kretz et al. 2006): 1.3-1.9 people/(m s) for 1 m wide ones.
BAND = (1.3, 1.9)
MODELS = ["orca", "social_force"]
COLOURS = {"orca": "#1f77b4", "social_force": "#d62728", "weidmann": "#222222", "band": "#bbbbbb"}


def weidmann(density):
    if density >= 5.4:
        return 0.0
    return 1.34 * (1 - math.exp(-1.913 * (1 / density - 1 / 5.4)))


def fundamental_diagram(build, preset, seeds):
    out = subprocess.run([os.path.join(build, "bench", "fundamental_diagram"), preset, str(seeds)],
                         check=True, capture_output=True, text=True).stdout
    points, errors = {m: [] for m in MODELS}, {}
    for line in out.splitlines():
        words = line.split()
        if len(words) == 5 and words[0] in MODELS:
            points[words[0]].append((float(words[1]), float(words[2])))
        elif len(words) >= 5 and words[0] in MODELS and words[1] == "mean":
            errors[words[0]] = float(words[4])
    return points, errors


def bottleneck(width, preset, avoidance):
    """The 1 m scenario with its corridor's walls moved to leave `width` clear."""
    with open(os.path.join(SOURCE, "scenarios", "verification", "bottleneck_1m.json")) as f:
        document = json.load(f)
    half = width / 2 + 0.1  # walls are 0.2 m thick, drawn on their centre lines
    walls = [w for w in document["world"]["walls"] if not (w["from"][0] >= 8 and w["to"][0] >= 8)]
    walls.append({"from": [8, 0], "to": [8, 4 - half], "thickness": 0.2})
    walls.append({"from": [8, 4 + half], "to": [8, 8], "thickness": 0.2})
    walls.append({"from": [8, 4 - half], "to": [12, 4 - half], "thickness": 0.2})
    walls.append({"from": [8, 4 + half], "to": [12, 4 + half], "thickness": 0.2})
    document["world"]["walls"] = walls
    document["locomotion"] = {"preset": preset, "avoidance": avoidance}
    return document


def steady_flow(times):
    """People per second between the first and last tenth of the leavers (as the unit test counts)."""
    first, last = len(times) // 10, len(times) - 1 - len(times) // 10
    return (last - first) / (times[last] - times[first])


def bottleneck_flow(build, width, preset, avoidance, seed):
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(bottleneck(width, preset, avoidance), f)
        path = f.name
    try:
        out = subprocess.run([os.path.join(build, "server", "app", "hrisim"), "run", path, "--seed", str(seed), "--events"],
                             check=True, capture_output=True, text=True).stdout
    finally:
        os.unlink(path)
    result = json.loads(out)
    times = sorted(e["time"] for e in result["event_log"] if e["kind"] == "left")
    return steady_flow(times), len(times), len(result["agents"])


def svg_plot(path, title, x_label, y_label, x_max, y_max, series, band=None, curve=None):
    """A line-and-marker plot: series is [(label, colour, [(x, y)])]; band a polygon [(x, y)]; curve a
    function drawn as a line."""
    width, height, left, bottom, top, right = 560, 380, 60, 50, 30, 150
    sx = lambda x: left + (width - left - right) * x / x_max
    sy = lambda y: height - bottom - (height - bottom - top) * y / y_max
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif" font-size="12">',
             f'<rect width="{width}" height="{height}" fill="white"/>',
             f'<text x="{width / 2 - right / 2}" y="18" text-anchor="middle" font-size="14">{title}</text>']
    for k in range(6):
        x, y = x_max * k / 5, y_max * k / 5
        parts.append(f'<line x1="{sx(x)}" y1="{sy(0)}" x2="{sx(x)}" y2="{sy(y_max)}" stroke="#eee"/>')
        parts.append(f'<line x1="{sx(0)}" y1="{sy(y)}" x2="{sx(x_max)}" y2="{sy(y)}" stroke="#eee"/>')
        parts.append(f'<text x="{sx(x)}" y="{sy(0) + 16}" text-anchor="middle">{x:g}</text>')
        parts.append(f'<text x="{sx(0) - 6}" y="{sy(y) + 4}" text-anchor="end">{y:.2g}</text>')
    parts.append(f'<line x1="{sx(0)}" y1="{sy(0)}" x2="{sx(x_max)}" y2="{sy(0)}" stroke="black"/>')
    parts.append(f'<line x1="{sx(0)}" y1="{sy(0)}" x2="{sx(0)}" y2="{sy(y_max)}" stroke="black"/>')
    parts.append(f'<text x="{(sx(0) + sx(x_max)) / 2}" y="{height - 12}" text-anchor="middle">{x_label}</text>')
    parts.append(f'<text transform="translate(16 {(sy(0) + sy(y_max)) / 2}) rotate(-90)" text-anchor="middle">{y_label}</text>')
    legend = []
    if band:
        points = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in band[1])
        parts.append(f'<polygon points="{points}" fill="{COLOURS["band"]}" fill-opacity="0.5"/>')
        legend.append((band[0], COLOURS["band"], False))
    if curve:
        points = " ".join(f"{sx(x):.1f},{sy(curve[1](x)):.1f}" for x in [x_max * k / 100 for k in range(4, 101)])
        parts.append(f'<polyline points="{points}" fill="none" stroke="{COLOURS["weidmann"]}" stroke-width="2"/>')
        legend.append((curve[0], COLOURS["weidmann"], False))
    for label, colour, points in series:
        line = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in points)
        parts.append(f'<polyline points="{line}" fill="none" stroke="{colour}" stroke-dasharray="4 3"/>')
        parts += [f'<circle cx="{sx(x):.1f}" cy="{sy(y):.1f}" r="4" fill="{colour}"/>' for x, y in points]
        legend.append((label, colour, True))
    for k, (label, colour, marker) in enumerate(legend):
        y = top + 20 + 20 * k
        x = width - right + 12
        parts.append(f'<circle cx="{x}" cy="{y - 4}" r="4" fill="{colour}"/>' if marker else
                     f'<rect x="{x - 6}" y="{y - 8}" width="12" height="8" fill="{colour}"/>')
        parts.append(f'<text x="{x + 10}" y="{y}">{label}</text>')
    parts.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(parts) + "\n")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--svg-dir", default=None)
    args = parser.parse_args()

    print("## Fundamental diagram (periodic corridor 20 m x 2 m, 0.4 m bodies), preset calibrated,", args.seeds, "seeds\n")
    points, errors = fundamental_diagram(args.build, "calibrated", args.seeds)
    hrisim_points, hrisim_errors = fundamental_diagram(args.build, "hrisim", 1)
    print("| density (people/m²) | Weidmann (m/s) | ORCA | social force | ORCA, hrisim's defaults | social force, hrisim's defaults |")
    print("|---|---|---|---|---|---|")
    for k, (density, speed) in enumerate(points["orca"]):
        print(f"| {density:.1f} | {weidmann(density):.2f} | {speed:.2f} | {points['social_force'][k][1]:.2f} | "
              f"{hrisim_points['orca'][k][1]:.2f} | {hrisim_points['social_force'][k][1]:.2f} |")
    print(f"| mean absolute error | | {errors['orca']:.3f} | {errors['social_force']:.3f} | {hrisim_errors['orca']:.3f} | {hrisim_errors['social_force']:.3f} |\n")

    print("## Bottleneck flow (room of 90, corridor 4 m long), people/s, seeds 1-" + str(args.seeds) + "\n")
    print("| width (m) | literature band | ORCA, calibrated | social force, calibrated | ORCA, hrisim's defaults | social force, hrisim's defaults |")
    print("|---|---|---|---|---|---|")
    flows = {}
    for width in WIDTHS:
        row = []
        for preset in ["calibrated", "hrisim"]:
            for avoidance in MODELS:
                runs = [bottleneck_flow(args.build, width, preset, avoidance, seed) for seed in range(1, args.seeds + 1)]
                flow = sum(r[0] for r in runs) / len(runs)
                flows[(preset, avoidance, width)] = flow
                out = sum(r[1] for r in runs)
                total = sum(r[2] for r in runs)
                row.append(f"{flow:.2f}" + ("" if out == total else f" ({out} of {total} out)"))
        print(f"| {width:.1f} | {BAND[0] * width:.2f}–{BAND[1] * width:.2f} | " + " | ".join(row) + " |")

    if args.svg_dir:
        svg_plot(os.path.join(args.svg_dir, "crowd_fundamental_diagram.svg"), "Speed against density, periodic corridor",
                 "density (people/m²)", "speed (m/s)", 4.5, 1.5,
                 [("ORCA, calibrated", COLOURS["orca"], points["orca"]),
                  ("social force, calibrated", COLOURS["social_force"], points["social_force"]),
                  ("ORCA, hrisim", "#9ecae1", hrisim_points["orca"])],
                 curve=("Weidmann 1993", weidmann))
        band = [(w, BAND[0] * w) for w in (0.6, 2.2)] + [(w, BAND[1] * w) for w in (2.2, 0.6)]
        svg_plot(os.path.join(args.svg_dir, "crowd_bottleneck_flow.svg"), "Flow through a bottleneck against its width",
                 "clear width (m)", "flow (people/s)", 2.4, 4.5,
                 [(f"{'ORCA' if m == 'orca' else 'social force'}, {p}", colour, [(w, flows[(p, m, w)]) for w in WIDTHS])
                  for p, m, colour in [("calibrated", "orca", COLOURS["orca"]), ("calibrated", "social_force", COLOURS["social_force"]),
                                       ("hrisim", "orca", "#9ecae1")]],
                 band=("1.3–1.9 people/(m·s)", band))


if __name__ == "__main__":
    main()
