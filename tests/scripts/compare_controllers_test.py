#!/usr/bin/env python3
"""scripts/compare-controllers against the real hrisim binary (ctest's compare_controllers_script).

    HRISIM_BINARY=build/test/server/app/hrisim python3 tests/scripts/compare_controllers_test.py -v

Runs the script with two seeds, the controllers goal and social, on the bundled elevator and on a
copy of the apartment whose robot drives to the kitchen under a goal controller (radius 0.3 m), into a
scratch database. Then it checks the table against the runs' reports as `hrisim serve` gives them for
the same database: every pair has a row or says why hrisim refused it, the controller kept the
scenario's goal, every number equals the report's to the digits shown, --skip-run prints the same
table, and a newer run of a pair replaces the older one. Without HRISIM_BINARY it uses
build/test/server/app/hrisim. Python 3 standard library only.
"""

import contextlib
import json
import os
import re
import shlex
import shutil
import signal
import sqlite3
import subprocess
import tempfile
import unittest
import urllib.request

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(REPO, "scripts", "compare-controllers")
BINARY = os.path.abspath(os.environ.get("HRISIM_BINARY") or os.path.join(REPO, "build", "test", "server", "app", "hrisim"))
CONTROLLERS = ["goal", "social"]
GOAL = {"location": "kitchen", "radius": 0.3}
DRIVEN = "apartment_to_kitchen"  # the scenario whose robot has a goal
CELL = re.compile(r"^(-?\d+(?:\.(\d+))?)(?: \[(-?[\d.]+), (-?[\d.]+)\])?(?: \(n=(\d+)\))?$")
LISTENING = re.compile(r"listening on (http://127\.0\.0\.1:\d+)")


def table_rows(markdown):
    """{(scenario, controller): cells} of the table's body, and the lines of the list under it."""
    rows, notes = {}, []
    for line in markdown.splitlines():
        if line.startswith("| ") and not line.startswith("| Scenario |"):
            cells = [cell.strip() for cell in line.strip("|").split("|")]
            rows[(cells[0], cells[1])] = cells
        elif line.startswith("- "):
            notes.append(line)
    return rows, notes


def write_driven_scenario(folder):
    """The apartment with a goal controller, and the person lingering long enough for the robot to get there."""
    with open(os.path.join(REPO, "scenarios", "apartment.json"), encoding="utf-8") as file:
        document = json.load(file)
    document["name"] = DRIVEN
    document["robots"][0]["controller"] = {"type": "goal", "goal": GOAL}
    document["steps"].append({"name": "linger", "actions": [{"agent": "person", "wait": {"duration": 30}}]})
    path = os.path.join(folder, DRIVEN + ".json")
    with open(path, "w", encoding="utf-8") as file:
        json.dump(document, file)
    return path


class CompareControllersTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.access(BINARY, os.X_OK):
            raise AssertionError("no hrisim binary at %s: build it or set HRISIM_BINARY" % BINARY)
        cls.dir = tempfile.mkdtemp(prefix="hrisim-compare-")
        cls.addClassCleanup(shutil.rmtree, cls.dir, ignore_errors=True)  # also when the rest of setUpClass fails
        cls.db = os.path.join(cls.dir, "controllers.db")
        cls.markdown = os.path.join(cls.dir, "table.md")
        cls.driven = write_driven_scenario(cls.dir)
        cls.arguments = [SCRIPT, "--scenarios", "elevator", cls.driven, "--controllers", ",".join(CONTROLLERS),
                         "--seeds", "1-2", "--db", cls.db, "--hrisim", BINARY]
        cls.first = cls.compare(*cls.arguments, "--markdown", cls.markdown)
        cls.skipped = cls.compare(*cls.arguments, "--skip-run")
        # A newer run of one pair, with one seed: it must replace that pair's row.
        cls.newer = cls.compare(SCRIPT, "--scenarios", cls.driven, "--controllers", "goal", "--seeds", "3",
                                "--db", cls.db, "--hrisim", BINARY)
        cls.final = cls.compare(*cls.arguments, "--skip-run")
        cls.reports = cls.stored_reports()

    @classmethod
    def compare(cls, *command):
        done = subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=240)
        if done.returncode not in (0, 1):
            raise AssertionError("%s exited %d:\n%s" % (shlex.join(command), done.returncode, done.stderr))
        return done

    @classmethod
    def stored_reports(cls):
        """{run id: report} of every run in the database, from `hrisim serve` on it."""
        with contextlib.closing(sqlite3.connect(cls.db)) as db:
            ids = [row[0] for row in db.execute("SELECT id FROM runs")]
        env = dict(os.environ, HRISIM_SCENARIOS=os.path.join(REPO, "scenarios"))
        env.pop("HRISIM_TOKEN", None)
        server = subprocess.Popen([BINARY, "serve", "--host", "127.0.0.1", "--port", "0", "--db", cls.db, "--log-requests", "0"],
                                  cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            output = ""
            for line in server.stdout:
                output += line
                listening = LISTENING.search(line)
                if listening:
                    url = listening.group(1)
                    break
            else:
                raise AssertionError("hrisim serve did not start:\n" + output)
            reports = {}
            for run_id in ids:
                with urllib.request.urlopen("%s/api/v1/runs/%s" % (url, run_id), timeout=30) as reply:
                    reports[run_id] = json.load(reply)
            return reports
        finally:
            server.send_signal(signal.SIGTERM)
            server.wait(20)
            server.stdout.close()

    def refusal(self, scenario, controller):
        """hrisim's own refusal of a controller for a scenario, or None when it accepts it."""
        done = subprocess.run([BINARY, "run", os.path.join(REPO, "scenarios", scenario + ".json"), "--max-time", "0.05",
                               "--controller", json.dumps({"type": controller})], cwd=REPO, capture_output=True, text=True)
        return done.stderr.splitlines()[0] if done.returncode == 2 else None

    def assertCell(self, cell, aggregate, scale, finished, what):
        """The cell shows the aggregate's mean [ci95_low, ci95_high] (times scale) to its digits, and its count when short."""
        if aggregate["count"] == 0:
            self.assertEqual(cell, "—", what)
            return
        match = CELL.match(cell)
        self.assertIsNotNone(match, "%s: %r" % (what, cell))
        tolerance = 0.5 * 10 ** -len(match.group(2) or "") + 1e-9
        self.assertAlmostEqual(float(match.group(1)), aggregate["mean"] * scale, delta=tolerance, msg=what)
        if aggregate["ci95_low"] is None:
            self.assertIsNone(match.group(3), what)
        else:
            self.assertAlmostEqual(float(match.group(3)), aggregate["ci95_low"] * scale, delta=tolerance, msg=what)
            self.assertAlmostEqual(float(match.group(4)), aggregate["ci95_high"] * scale, delta=tolerance, msg=what)
        self.assertEqual(match.group(5), None if aggregate["count"] == finished else str(aggregate["count"]), what)

    def assertRowMatchesReport(self, cells, report):
        what = "%s × %s" % (cells[0], cells[1])
        self.assertEqual(cells[-1], "`%s`" % report["id"], what)
        finished = report["progress"]["finished"]
        self.assertEqual(cells[2], str(finished), what)
        aggregates = report["aggregates"]
        self.assertCell(cells[3], aggregates["success"], 100, finished, what + ", success")
        # The report has the collision rate without an interval: the mean alone is compared.
        self.assertAlmostEqual(float(CELL.match(cells[4]).group(1)), report["rates"]["collision_rate"] * 100, delta=0.5, msg=what)
        self.assertCell(cells[5], aggregates["collisions"], 1, finished, what + ", collisions")
        self.assertCell(cells[6], aggregates["time_to_goal"], 1, finished, what + ", time to goal")
        self.assertCell(cells[7], aggregates["minimum_distance_to_people"], 1, finished, what + ", minimum distance")
        self.assertCell(cells[8], aggregates["intimate_space_intrusions"], 1, finished, what + ", intimate space")

    def test_every_pair_has_a_row_or_hrisims_reason_and_the_exit_status_says_so(self):
        rows, notes = table_rows(self.first.stdout)
        refused = 0
        for controller in CONTROLLERS:
            self.assertIn((DRIVEN, controller), rows)
            reason = self.refusal("elevator", controller)
            if reason is None:
                self.assertIn(("elevator", controller), rows)
            else:
                refused += 1
                self.assertNotIn(("elevator", controller), rows)
                self.assertIn("- elevator × %s: hrisim refused it: %s" % (controller, reason), notes)
        self.assertEqual(len(rows), 2 * len(CONTROLLERS) - refused)
        self.assertEqual(self.first.returncode, 1 if refused else 0)

    def test_the_numbers_are_those_of_the_stored_reports(self):
        rows, _ = table_rows(self.first.stdout)
        for cells in rows.values():
            self.assertRowMatchesReport(cells, self.reports[cells[-1].strip("`")])
        # The goal controller reaches the kitchen, the social one waits behind the person there: the
        # table has a time to goal and a "—" for it.
        self.assertNotEqual(rows[(DRIVEN, "goal")][6], "—")
        self.assertEqual(rows[(DRIVEN, "social")][6], "—")

    def test_the_controller_keeps_the_scenarios_goal_and_radius(self):
        rows, _ = table_rows(self.first.stdout)
        for controller in CONTROLLERS:
            report = self.reports[rows[(DRIVEN, controller)][-1].strip("`")]
            self.assertEqual(report["controller"], controller)
            self.assertEqual(report["config"]["controller"], {"type": controller, "goal": GOAL})
            self.assertEqual(report["config"]["seeds"], [1, 2])

    def test_skip_run_builds_the_same_table_from_the_database(self):
        rows, notes = table_rows(self.first.stdout)
        skipped_rows, skipped_notes = table_rows(self.skipped.stdout)
        self.assertEqual(skipped_rows, rows)
        # What hrisim refused in the first call was not run again: nothing of it is stored.
        self.assertEqual(skipped_notes, [re.sub(r": hrisim refused it: .*", ": no ended run of this pair is stored", n) for n in notes])
        self.assertEqual(self.skipped.returncode, self.first.returncode)

    def test_the_markdown_file_names_the_command_that_made_it(self):
        with open(self.markdown, encoding="utf-8") as file:
            text = file.read()
        command = shlex.join(self.arguments + ["--markdown", self.markdown])
        self.assertTrue(text.startswith("# Controller comparison\n\nMade by `%s` with hrisim " % command), text[:400])
        self.assertTrue(text.endswith(self.first.stdout))

    def test_the_latest_run_of_a_pair_wins(self):
        self.assertEqual(self.newer.returncode, 0, self.newer.stderr)
        before, _ = table_rows(self.first.stdout)
        after, _ = table_rows(self.final.stdout)
        self.assertEqual(set(after), set(before))
        newer = after[(DRIVEN, "goal")]
        self.assertNotEqual(newer[-1], before[(DRIVEN, "goal")][-1])
        self.assertEqual(self.reports[newer[-1].strip("`")]["config"]["seeds"], [3])
        self.assertRowMatchesReport(newer, self.reports[newer[-1].strip("`")])
        for pair in set(after) - {(DRIVEN, "goal")}:
            self.assertEqual(after[pair], before[pair])

    def test_bad_arguments_exit_2_before_running_anything(self):
        for arguments in (["--seeds", "1..3"], ["--scenarios", "no_such_scenario"], ["--jobs", "0"]):
            done = subprocess.run([SCRIPT, "--db", os.path.join(self.dir, "unused.db"), "--hrisim", BINARY, *arguments],
                                  cwd=REPO, capture_output=True, text=True)
            self.assertEqual(done.returncode, 2, arguments)
            self.assertFalse(os.path.exists(os.path.join(self.dir, "unused.db")), arguments)


if __name__ == "__main__":
    unittest.main()
