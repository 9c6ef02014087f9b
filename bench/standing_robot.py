#!/usr/bin/env python3
"""Clearance that people keep from the robot, over many seeds (stdlib only).

For each scenario and seed it runs `hrisim run SCENARIO --seed N --events --trajectory T.csv`,
then computes, for every person, the smallest surface clearance to the first robot over the
episode (centre distance minus both radii) from the 10 Hz trajectory. A person "passes" the
robot when they come within --pass-distance (2 m, centre to centre) of it. It prints a Markdown
table per scenario and, with --details N, the N closest passers and every person contact.

  bench/standing_robot.py --seeds 1-20 --scenarios corridor_passing queue conversation_group elevator
"""
import argparse, csv, json, os, statistics, subprocess, sys, tempfile, time
from collections import Counter, defaultdict
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_HUMAN_RADIUS = 0.3   # server/scenario/model.hpp kDefaultAgentRadius
DEFAULT_ROBOT_RADIUS = 0.3   # a robot without a model is a disc of 0.3 m


def parse_seeds(text):
    seeds = []
    for part in text.split(","):
        a, _, b = part.partition("-")
        seeds += list(range(int(a), int(b or a) + 1))
    return seeds


def percentile(values, p):
    """Linear interpolation between closest ranks (numpy's default)."""
    if not values:
        return None
    v = sorted(values)
    k = (len(v) - 1) * p / 100.0
    lo = int(k)
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (v[hi] - v[lo]) * (k - lo)


def load_scenario(path):
    with open(path) as f:
        scen = json.load(f)
    human_radius = {h["id"]: h.get("radius", DEFAULT_HUMAN_RADIUS) for h in scen["humans"]}
    robot = scen["robots"][0]
    if "model" in robot:
        with open(os.path.join(ROOT, "assets", "robots", robot["model"] + ".json")) as f:
            robot_radius = json.load(f)["footprint_radius"]
    else:
        robot_radius = robot.get("radius", DEFAULT_ROBOT_RADIUS)
    return scen, human_radius, robot["id"], robot_radius


def describe_action(action):
    """One choreography action in a few words, e.g. 'goto social_space:line'."""
    kind = next(k for k in action if k not in ("agent", "group"))
    arg = action[kind]
    if isinstance(arg, dict):
        keys = [k for k in ("location", "social_space", "agent", "routine", "topic", "duration") if k in arg]
        if keys:
            return f"{kind} {keys[0]}:{arg[keys[0]]}"
        if "pose" in arg:
            return f"{kind} pose({arg['pose']['x']},{arg['pose']['y']})"
    return f"{kind} {arg}"


def run_hrisim(binary, scenario_path, seed, tmpdir, retries=5):
    """One episode; returns (summary, trajectory path). Retries if the binary is being rebuilt."""
    traj = os.path.join(tmpdir, f"{os.path.basename(scenario_path)}.{seed}.csv")
    cmd = [binary, "run", scenario_path, "--seed", str(seed), "--events", "--trajectory", traj]
    for attempt in range(retries):
        try:
            out = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, check=True)
            return json.loads(out.stdout), traj
        except (subprocess.CalledProcessError, OSError, json.JSONDecodeError) as err:
            if attempt == retries - 1:
                raise RuntimeError(f"{' '.join(cmd)} failed: {err}") from err
            time.sleep(10)


def closest_approaches(traj_path, human_radius, robot_id, robot_radius):
    """Per person: (clearance, time, smallest centre distance) at their closest 10 Hz sample."""
    poses = defaultdict(dict)  # tick -> agent -> (time, x, y)
    with open(traj_path) as f:
        for row in csv.DictReader(f):
            poses[int(row["tick"])][row["agent"]] = (float(row["time"]), float(row["x"]), float(row["y"]))
    best = {}
    for tick in sorted(poses):
        agents = poses[tick]
        if robot_id not in agents:
            continue
        _, rx, ry = agents[robot_id]
        for person, radius in human_radius.items():
            if person not in agents:
                continue
            t, x, y = agents[person]
            centre = ((x - rx) ** 2 + (y - ry) ** 2) ** 0.5
            clearance = centre - radius - robot_radius
            if person not in best or clearance < best[person][0]:
                best[person] = (clearance, t, centre)
    return best


def step_at(summary, t):
    """Name of the choreography step running at time t (the last one started by then)."""
    current = None
    for step in summary.get("steps", []):
        if step.get("started") is not None and step["started"] <= t + 1e-9:
            current = step
    return current["name"] if current else None


def doing(scen, summary, person, t):
    """What the person was asked to do at time t: their actions in the current step, plus
    any robot request they had accepted by then."""
    name = step_at(summary, t)
    step = next((s for s in scen["steps"] if s["name"] == name), None)
    acts = [describe_action(a) for a in (step or {}).get("actions", []) if a.get("agent") == person]
    for e in summary.get("event_log", []):
        if e["kind"] == "request_accepted" and e["subject"] == person and e["time"] <= t:
            acts.append(f"answering request {e['data'].get('routine')} (accepted t={e['time']:.1f})")
    return name, "; ".join(acts) or "(no action in this step)"


def fmt(x, digits=2):
    return "–" if x is None else f"{x:.{digits}f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hrisim", default=os.path.join(ROOT, "build/test/server/app/hrisim"), help="hrisim binary")
    ap.add_argument("--seeds", default="1-20", help="A-B or A,B,C (default 1-20)")
    ap.add_argument("--scenarios", nargs="+", default=["corridor_passing", "queue", "conversation_group", "elevator"],
                    help="scenario names in scenarios/ or paths to .json files")
    ap.add_argument("--pass-distance", type=float, default=2.0, help="centre distance that counts as passing (m)")
    ap.add_argument("--threshold", type=float, default=0.4, help="target median clearance (m)")
    ap.add_argument("--details", type=int, default=10, help="list this many closest passers per scenario")
    ap.add_argument("--jobs", type=int, default=2, help="episodes at once")
    args = ap.parse_args()
    seeds = parse_seeds(args.seeds)
    args.hrisim = os.path.abspath(args.hrisim)
    version = json.loads(subprocess.run([args.hrisim, "version"], capture_output=True, text=True).stdout or "{}")

    rows, details = [], []
    with tempfile.TemporaryDirectory() as tmpdir, ThreadPoolExecutor(args.jobs) as pool:
        for name in args.scenarios:
            path = os.path.abspath(name) if name.endswith(".json") else os.path.join(ROOT, "scenarios", name + ".json")
            scen, human_radius, robot_id, robot_radius = load_scenario(path)
            results = list(pool.map(lambda s: (s, run_hrisim(args.hrisim, path, s, tmpdir)), seeds))
            passers, contacts, min_dists, intimate, successes = [], [], [], [], 0
            collisions, robot_blamed, contact_episodes, terminations = 0, 0, 0, Counter()
            for seed, (summary, traj) in results:
                m = summary["metrics"]
                terminations[summary["termination"]] += 1
                successes += (m.get("success") or 0) >= 1
                collisions += int(m.get("collisions") or 0)
                robot_blamed += int(m.get("robot_on_person_collisions") or 0)
                if m.get("minimum_distance_to_people") is not None:
                    min_dists.append(m["minimum_distance_to_people"])
                if m.get("intimate_space_intrusions") is not None:
                    intimate.append(m["intimate_space_intrusions"])
                # Contacts with a person (contact_start events; robots with a model emit them).
                touched = [e for e in summary.get("event_log", [])
                           if e["kind"] == "contact_start" and e["data"].get("with") in human_radius]
                contacts += [(seed, e) for e in touched]
                # Disc robots emit no contact events: their contacts show in the collisions metric.
                contact_episodes += bool(touched) or (m.get("collisions") or 0) > 0
                for person, (clear, t, centre) in closest_approaches(traj, human_radius, robot_id, robot_radius).items():
                    if centre <= args.pass_distance:
                        passers.append((clear, seed, person, t, summary))
                os.remove(traj)
            clearances = [p[0] for p in passers]
            rows.append({
                "scenario": scen["name"], "r": robot_radius, "episodes": len(seeds),
                "passers": len(passers), "median": statistics.median(clearances) if clearances else None,
                "p10": percentile(clearances, 10), "min": min(clearances) if clearances else None,
                "below": sum(c < args.threshold for c in clearances),
                "contact_eps": contact_episodes, "contacts": len(contacts), "collisions": collisions, "robot_blamed": robot_blamed,
                "mind_min": min(min_dists) if min_dists else None,
                "mind_med": statistics.median(min_dists) if min_dists else None,
                "intimate": statistics.mean(intimate) if intimate else None,
                "success": successes / len(seeds),
                "term": ", ".join(f"{k}×{v}" for k, v in terminations.most_common()),
            })
            lines = [f"### {scen['name']}: {min(args.details, len(passers))} closest passers (clearance, seed, person, t, step, actions)"]
            for clear, seed, person, t, summary in sorted(passers, key=lambda p: p[0])[:args.details]:
                step, acts = doing(scen, summary, person, t)
                lines.append(f"- {clear:.3f} m  seed {seed}  {person}  t={t:.1f} s  step `{step}`: {acts}")
            by_person = defaultdict(list)
            for clear, _, person, _, _ in passers:
                by_person[person].append(clear)
            lines.append("- per person (passes, median, min): " + ", ".join(
                f"{p} {len(v)}, {statistics.median(v):.3f}, {min(v):.3f}" for p, v in sorted(by_person.items())))
            # Contacts grouped by seed, person and step: first and last time, count, body parts.
            touches = defaultdict(list)
            for seed, e in contacts:
                summary = dict(results)[seed][0]
                step, acts = doing(scen, summary, e["data"]["with"], e["time"])
                touches[(seed, e["data"]["with"], step, acts)].append(e)
            for (seed, person, step, acts), es in touches.items():
                parts = ",".join(sorted({e["data"].get("part", "?") for e in es}))
                lines.append(f"- contact: seed {seed} {person} ×{len(es)} t={es[0]['time']:.2f}–{es[-1]['time']:.2f} s "
                             f"({parts}) step `{step}`: {acts}")
            details.append("\n".join(lines))

    print(f"hrisim {version.get('git_commit', '?')}. Seeds {args.seeds}; clearance = centre distance − person radius − robot radius (r), from the "
          f"10 Hz trajectory; passers come within {args.pass_distance} m centre to centre; "
          f"min dist and intimate % are hrisim's metrics (every tick).\n")
    print("| scenario | r (m) | passers | median clearance | p10 | min | passers < "
          f"{args.threshold} m | episodes with contact | contact events | collisions (metric; robot-on-person) | "
          "min dist min / median | intimate % (closest < 0.45 m; mean) | success | termination |")
    print("|---|" + "---|" * 13)
    for r in rows:
        print(f"| {r['scenario']} | {r['r']} | {r['passers']} | {fmt(r['median'], 3)} | {fmt(r['p10'], 3)} | "
              f"{fmt(r['min'], 3)} | {r['below']} | {r['contact_eps']}/{r['episodes']} | {r['contacts']} | "
              f"{r['collisions']}; {r['robot_blamed']} | {fmt(r['mind_min'], 3)} / {fmt(r['mind_med'], 3)} | {fmt(r['intimate'], 1)} | "
              f"{r['success']:.0%} | {r['term']} |")
    print()
    print("\n\n".join(details))


if __name__ == "__main__":
    sys.exit(main())
