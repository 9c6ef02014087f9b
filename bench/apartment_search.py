#!/usr/bin/env python3
"""Seed 000's apartment search: ARTOS looks for Anna in scenarios/apartment_search.json, by presence
probability and by a naive sweep, over many seeds (stdlib only).

For each strategy it runs `hrisim run scenarios/apartment_search.json --seeds S --controller
'{"type": "search", "person": "anna", "strategy": STRATEGY}' --db DB`, then reads from the database
each episode's time_to_find and path_length, the rooms the robot looked into (events search_room),
where Anna was found, and the time of day the episode started (the first stay_started's `at`). It
prints Markdown tables: per strategy, and per strategy and time of day.

  bench/apartment_search.py --seeds 1-50 --hrisim build/benchrel/server/app/hrisim
"""
import argparse, json, os, sqlite3, statistics, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STRATEGIES = ("presence", "sweep")
BANDS = (("07–10", 7, 10), ("10–13", 10, 13), ("13–17", 13, 17), ("17–22", 17, 22))


def quartiles(values):
    """(first quartile, median, third quartile) by linear interpolation; None when empty."""
    if not values:
        return None
    v = sorted(values)
    def at(p):
        k = (len(v) - 1) * p
        lo = int(k)
        hi = min(lo + 1, len(v) - 1)
        return v[lo] + (v[hi] - v[lo]) * (k - lo)
    return at(0.25), at(0.5), at(0.75)


def episodes(db):
    """Per episode: seed, time_to_find (None if not found), path_length, rooms looked into, start hour."""
    con = sqlite3.connect(db)
    rows = []
    for episode, seed in con.execute("select id, seed from episodes order by seed"):
        metric = dict(con.execute("select key, value from metric_values where episode_id = ?", (episode,)).fetchall())
        events = [(kind, subject, json.loads(data), tick) for kind, subject, data, tick in
                  con.execute("select kind, subject, data, tick from events where episode_id = ? order by seq", (episode,))]
        rooms = [data["room"] for kind, _, data, _ in events if kind == "search_room"]
        start = next(data["at"] for kind, subject, data, _ in events if kind == "stay_started" and subject == "anna")
        # Where Anna's schedule had her when the robot set off to its first room.
        first_tick = next(tick for kind, _, _, tick in events if kind == "search_room")
        anna_then = [data["room"] for kind, subject, data, tick in events if kind == "stay_started" and subject == "anna" and tick <= first_tick][-1]
        hours, minutes, _ = (int(x) for x in start.split(":"))
        found = next((data for kind, _, data, _ in events if kind == "person_found"), None)
        rows.append({"seed": seed, "time": metric.get("time_to_find"), "length": metric["path_length"], "rooms": rooms,
                     "start": hours + minutes / 60, "found_in": found and found.get("room"),
                     "first_room_right": bool(rooms) and rooms[0] == anna_then})
    return rows


def summary(rows, time_limit):
    found = [r for r in rows if r["time"] is not None]
    t = quartiles([r["time"] if r["time"] is not None else time_limit for r in rows])
    length = quartiles([r["length"] for r in rows])
    first = sum(1 for r in found if len(r["rooms"]) == 1)
    right = sum(1 for r in rows if r["first_room_right"])
    looked = statistics.mean(len(r["rooms"]) for r in found) if found else float("nan")
    return (f"{len(found)}/{len(rows)} | {t[1]:.0f} ({t[0]:.0f}–{t[2]:.0f}) | {statistics.mean(r['time'] if r['time'] is not None else time_limit for r in rows):.0f} | "
            f"{length[1]:.1f} ({length[0]:.1f}–{length[2]:.1f}) | {looked:.1f} | {right} | {first}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", default="1-50")
    parser.add_argument("--hrisim", default=os.path.join(ROOT, "build", "release", "server", "app", "hrisim"))
    parser.add_argument("--jobs", default="2")
    args = parser.parse_args()
    scenario = os.path.join(ROOT, "scenarios", "apartment_search.json")
    with open(scenario) as f:
        time_limit = json.load(f)["time_limit"]
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for strategy in STRATEGIES:
            db = os.path.join(tmp, strategy + ".db")
            controller = json.dumps({"type": "search", "person": "anna", "strategy": strategy})
            subprocess.run([args.hrisim, "run", scenario, "--seeds", args.seeds, "--jobs", args.jobs, "--controller", controller, "--db", db],
                           cwd=ROOT, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            results[strategy] = episodes(db)
    print(f"Not found within the {time_limit} s limit counts as {time_limit} s in the search-time columns.\n")
    print("| strategy | found | search time, median (IQR), s | mean, s | path length, median (IQR), m | rooms looked into, mean (found) | she was in the first room | found in the first room |")
    print("|---|---|---|---|---|---|---|---|")
    for strategy, rows in results.items():
        print(f"| {strategy} | {summary(rows, time_limit)} |")
    print("\n| start (time of day) | strategy | found | search time, median (IQR), s | mean, s | path length, median (IQR), m | rooms looked into, mean (found) | she was in the first room | found in the first room |")
    print("|---|---|---|---|---|---|---|---|---|")
    for band, low, high in BANDS:
        for strategy, rows in results.items():
            chosen = [r for r in rows if low <= r["start"] < high]
            if chosen:
                print(f"| {band} | {strategy} | {summary(chosen, time_limit)} |")


if __name__ == "__main__":
    main()
