#!/usr/bin/env python3
"""One owner's seeks against another session's steps: four clients each seek their session one tick back
(then step one tick) again and again at tick TICK of the elevator kept going, while a fifth client steps
another session one tick at a time. Prints the fifth client's step latency (median, p99) and how many
seeks were answered and refused. Against a running server without tokens.
  usage: bench/seek_fairness.py URL [seconds=20] [tick=20000]"""
import json
import pathlib
import statistics
import sys
import threading
import time
import urllib.error
import urllib.request


def call(base, method, path, body=None):
    data = None if body is None else json.dumps(body).encode()
    request = urllib.request.Request(base + path, data=data, method=method, headers={"Content-Type": "application/json"})
    try:
        with urllib.request.urlopen(request, timeout=600) as reply:
            return reply.status, json.loads(reply.read() or b"null")
    except urllib.error.HTTPError as error:
        return error.code, json.loads(error.read() or b"null")


def main():
    base = sys.argv[1].rstrip("/")
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 20.0
    tick = int(sys.argv[3]) if len(sys.argv) > 3 else 20000
    elevator = json.loads((pathlib.Path(__file__).parent.parent / "scenarios" / "elevator.json").read_text())
    limit = tick / 60 + 600
    elevator["time_limit"] = limit
    elevator["steps"].append({"name": "linger", "actions": [{"agent": "ada", "wait": {"duration": limit}}]})
    status, uploaded = call(base, "POST", "/api/v1/scenarios", elevator)
    assert status == 201, uploaded
    scenario = uploaded["summary"]["id"]

    def create():
        status, created = call(base, "POST", "/api/v1/sessions", {"scenario": scenario, "seed": 1})
        assert status == 201, created
        return "/api/v1/sessions/" + created["id"]

    seekers = [create() for _ in range(4)]
    for session in seekers:
        call(base, "POST", session + "/step", {"n": tick})
    stepper = create()
    stop = time.monotonic() + seconds
    counts = {"answered": 0, "refused": 0}
    lock = threading.Lock()

    def seek(session):
        while time.monotonic() < stop:
            status, _ = call(base, "POST", session + "/seek", {"tick": tick - 1})
            with lock:
                counts["answered" if status == 200 else "refused"] += 1
            call(base, "POST", session + "/step", {"n": 1})

    latencies = []

    def step():
        while time.monotonic() < stop:
            start = time.monotonic()
            call(base, "POST", stepper + "/step", {"n": 1})
            latencies.append(time.monotonic() - start)

    threads = [threading.Thread(target=seek, args=(s,)) for s in seekers] + [threading.Thread(target=step)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    latencies.sort()
    print(f"seek_fairness: 4 clients seeking one tick back at tick {tick} for {seconds:.0f} s: "
          f"{counts['answered']} seeks answered, {counts['refused']} refused (503)")
    print(f"another session's 1-tick step: {len(latencies)} steps, median {statistics.median(latencies) * 1000:.1f} ms, "
          f"p99 {latencies[int(0.99 * (len(latencies) - 1))] * 1000:.1f} ms")


if __name__ == "__main__":
    main()
