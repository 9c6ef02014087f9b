"""REST client for hrisim's HTTP API (api/openapi.yaml), standard library only."""

import base64
import json
import time
import urllib.error
import urllib.parse
import urllib.request

from ._websocket import WebSocket, WebSocketError

DEFAULT_URL = "http://127.0.0.1:8080"

# Run statuses after which a run changes no more (RunStatus in api/openapi.yaml).
FINAL_RUN_STATUSES = ("finished", "failed", "cancelled", "interrupted")
FINAL_VIDEO_STATUSES = ("done", "failed", "cancelled")


class HrisimError(Exception):
    """An error answer of the server: ``{"error": {"code", "message", "details"}}``.

    ``status`` is the HTTP status (None for an error answer on the WebSocket), ``code`` the
    error code (``bad_request``, ``not_found``, ...), ``message`` the text and ``details`` a dict
    (e.g. ``{"pointer": "/action"}``).
    """

    def __init__(self, status, code, message, details=None):
        self.status = status
        self.code = code
        self.message = message
        self.details = details or {}
        prefix = "HTTP %s " % status if status is not None else ""
        super().__init__("%s%s: %s" % (prefix, code, message))

    @property
    def pointer(self):
        """``details["pointer"]``, the JSON pointer of the wrong field, or None."""
        return self.details.get("pointer")

    @classmethod
    def from_body(cls, status, body):
        """An error from a response body (bytes, str or an already decoded dict)."""
        data = body
        if isinstance(body, (bytes, bytearray)):
            body = body.decode("utf-8", "replace")
        if isinstance(body, str):
            try:
                data = json.loads(body)
            except ValueError:
                return cls(status, "http_%s" % status, body.strip() or "HTTP error %s" % status)
        error = data.get("error") if isinstance(data, dict) else None
        if not isinstance(error, dict):
            if isinstance(data, dict) and data.get("type") == "error":
                error = data
            else:
                return cls(status, "http_%s" % status, str(data))
        return cls(status, error.get("code"), error.get("message", ""), error.get("details"))


def _poll(fetch, final_statuses, what, timeout, interval):
    """``fetch()`` every ``interval`` s until its status is one of ``final_statuses`` → its last answer.

    Raises ``TimeoutError`` naming ``what`` when that takes more than ``timeout`` seconds.
    """
    deadline = time.monotonic() + timeout
    while True:
        answer = fetch()
        if answer.get("status") in final_statuses:
            return answer
        if time.monotonic() >= deadline:
            raise TimeoutError("%s still %s after %s s" % (what, answer.get("status"), timeout))
        time.sleep(interval)


class Client:
    """hrisim's REST API. ``Client(url="http://127.0.0.1:8080", token=None)``.

    Every method returns the decoded JSON answer; an error answer raises ``HrisimError``.
    """

    def __init__(self, url=DEFAULT_URL, token=None, timeout=60.0):
        self.url = url.rstrip("/")
        self.token = token
        self.timeout = timeout

    def __repr__(self):
        return "Client(%r)" % self.url

    # -- plumbing ----------------------------------------------------------------------------
    def _headers(self):
        headers = {"Accept": "application/json"}
        if self.token:
            headers["Authorization"] = "Bearer " + self.token
        return headers

    def request(self, method, path, body=None, params=None, raw=False, timeout=None, data=None, content_type=None):
        """``method`` ``path`` with a JSON ``body`` (or bytes ``data`` of ``content_type``) → the decoded
        JSON (bytes with ``raw``)."""
        url = self.url + path
        if params:
            query = {k: v for k, v in params.items() if v is not None}
            if query:
                url += "?" + urllib.parse.urlencode(query)
        headers = self._headers()
        if data is not None:
            headers["Content-Type"] = content_type
        elif body is not None:
            data = json.dumps(body).encode("utf-8")
            headers["Content-Type"] = "application/json"
        elif method in ("POST", "PUT"):
            # Without a token, the server takes state-changing requests only as JSON (a foreign web
            # page cannot send that without asking); urllib would call an empty body a form.
            data = b""
            headers["Content-Type"] = "application/json"
        req = urllib.request.Request(url, data=data, headers=headers, method=method)
        try:
            with urllib.request.urlopen(req, timeout=timeout or self.timeout) as response:
                content = response.read()
                if raw:
                    return content
                if not content:
                    return None
                return json.loads(content.decode("utf-8"))
        except urllib.error.HTTPError as e:
            content = e.read()
            raise HrisimError.from_body(e.code, content) from None

    def get(self, path, **params):
        return self.request("GET", path, params=params)

    def post(self, path, body=None, **params):
        return self.request("POST", path, body=body, params=params)

    @staticmethod
    def _q(value):
        return urllib.parse.quote(str(value), safe="")

    # -- server ------------------------------------------------------------------------------
    def health(self):
        return self.get("/healthz")

    def version(self):
        return self.get("/api/v1/version")

    # -- scenarios ---------------------------------------------------------------------------
    def scenarios(self, limit=None):
        """Every scenario's summary (all pages followed) as a list."""
        items = []
        cursor = None
        while True:
            page = self.get("/api/v1/scenarios", limit=limit, cursor=cursor)
            items.extend(page.get("items", []))
            cursor = page.get("next_cursor")
            if not cursor:
                return items

    def scenario(self, scenario_id):
        return self.get("/api/v1/scenarios/" + self._q(scenario_id))

    def upload_scenario(self, document, files=None):
        """Store a scenario (a dict in hrisim's JSON format, or the text of an IMHuS or Pedsim file) →
        its summary, whose ``id`` sessions and runs name. ``files`` maps paths relative to the scenario
        (``"maps/lab.yaml"``) to the text or bytes of the files it names, uploaded alongside it. A
        scenario that is not valid raises HrisimError with every error's pointer."""
        if files is None and isinstance(document, dict):
            return self.post("/api/v1/scenarios", document)["summary"]
        bundle = {"scenario": document, "files": {}}
        for path, content in (files or {}).items():
            if isinstance(content, bytes):
                content = {"base64": base64.b64encode(content).decode("ascii")}
            bundle["files"][path] = content
        return self.post("/api/v1/scenarios", bundle)["summary"]

    # -- sessions ----------------------------------------------------------------------------
    def create_session(self, scenario, seed=0, controller=None, mode="lockstep", realtime_factor=None):
        body = {"scenario": scenario, "seed": seed, "mode": mode}
        if controller is not None:
            body["controller"] = controller
        if realtime_factor is not None:
            body["realtime_factor"] = realtime_factor
        return self.post("/api/v1/sessions", body)

    def start_from_snapshot(self, snapshot, mode="lockstep", realtime_factor=None):
        """A new session at the moment a snapshot file (a dict, as ``snapshot_file`` returns it) keeps:
        its scenario, seed, controller and inputs, simulated again to its tick on this server."""
        body = {"snapshot": snapshot, "mode": mode}
        if realtime_factor is not None:
            body["realtime_factor"] = realtime_factor
        return self.post("/api/v1/sessions", body)

    def take_snapshot(self, session_id):
        """Keeps the session's present moment → ``{"snapshot", "tick", "state_hash"}``."""
        return self.post("/api/v1/sessions/%s/snapshots" % self._q(session_id))

    def snapshot_file(self, session_id, snapshot_id):
        """A kept snapshot as a file (a dict; ``json.dump`` it to keep it), which ``start_from_snapshot``
        or ``reset(options={"snapshot": …})`` on any server of the same version goes back to."""
        return self.get("/api/v1/sessions/%s/snapshots/%s" % (self._q(session_id), self._q(snapshot_id)))

    def session_inputs(self, session_id):
        """What drove the session so far: its env steps, ticks, commands and placements, each with its tick."""
        return self.get("/api/v1/sessions/%s/inputs" % self._q(session_id))

    def sessions(self):
        return self.get("/api/v1/sessions")

    def session(self, session_id):
        return self.get("/api/v1/sessions/" + self._q(session_id))

    def delete_session(self, session_id):
        return self.request("DELETE", "/api/v1/sessions/" + self._q(session_id))

    def step_session(self, session_id, action=None, n=1):
        body = {"n": n}
        if action is not None:
            body["action"] = [float(a) for a in action]
        return self.post("/api/v1/sessions/%s/step" % self._q(session_id), body)

    def reset_session(self, session_id, seed=None, options=None):
        body = {}
        if seed is not None:
            body["seed"] = int(seed)
        if options is not None:
            body["options"] = options
        return self.post("/api/v1/sessions/%s/reset" % self._q(session_id), body)

    def action_space(self, session_id):
        return self.get("/api/v1/sessions/%s/action_space" % self._q(session_id))

    def observation_space(self, session_id):
        return self.get("/api/v1/sessions/%s/observation_space" % self._q(session_id))

    def session_state(self, session_id, events_since=None):
        return self.get("/api/v1/sessions/%s/state" % self._q(session_id), events_since=events_since)

    def session_metrics(self, session_id):
        return self.get("/api/v1/sessions/%s/metrics" % self._q(session_id))

    def cameras(self, session_id):
        return self.get("/api/v1/sessions/%s/cameras" % self._q(session_id))

    def commands(self, session_id, commands):
        return self.post("/api/v1/sessions/%s/commands" % self._q(session_id), {"commands": commands})

    def ws_ticket(self, session_id):
        return self.post("/api/v1/sessions/%s/ws-ticket" % self._q(session_id))

    def websocket(self, session_id, timeout=None):
        """An open WebSocket to the session (``hrisim._websocket.WebSocket``).

        With a token, opened with a single-use ticket from POST .../ws-ticket.
        """
        parts = urllib.parse.urlsplit(self.url)
        if parts.scheme != "http":
            raise HrisimError(None, "unsupported", "only http:// servers are supported, not %s" % self.url)
        base = "ws://" + parts.netloc + parts.path.rstrip("/")
        if self.token:
            path = self.ws_ticket(session_id)["url"]
        else:
            path = "/api/v1/sessions/%s/ws" % self._q(session_id)
        try:
            return WebSocket(base + path, timeout=timeout or self.timeout)
        except WebSocketError as e:
            if e.status is not None:
                raise HrisimError.from_body(e.status, e.body) from None
            raise

    # -- runs --------------------------------------------------------------------------------
    def start_run(self, scenario, seeds=None, count=None, controller=None, gates=None, max_time=None,
                  first_seed=None, requests=None):
        """POST /api/v1/runs → the run's report (its ``id`` to poll)."""
        body = {"scenario": scenario}
        if seeds is not None:
            body["seeds"] = [int(s) for s in seeds]
        if count is not None:
            body["count"] = int(count)
        if first_seed is not None:
            body["first_seed"] = int(first_seed)
        if controller is not None:
            body["controller"] = controller
        if gates is not None:
            body["gates"] = list(gates)
        if max_time is not None:
            body["max_time"] = max_time
        if requests is not None:
            body["requests"] = requests
        return self.post("/api/v1/runs", body)

    def runs(self, status=None, scenario=None, limit=None, cursor=None):
        """One page of runs, newest first: ``{"items", "next_cursor"}``."""
        return self.get("/api/v1/runs", status=status, scenario=scenario, limit=limit, cursor=cursor)

    def run(self, run_id):
        return self.get("/api/v1/runs/" + self._q(run_id))

    def cancel_run(self, run_id):
        return self.post("/api/v1/runs/%s/cancel" % self._q(run_id))

    def wait_run(self, run_id, timeout=600.0, interval=0.2):
        """Poll the run until it has ended (finished, failed, cancelled or interrupted) → its report.

        Raises ``TimeoutError`` when it has not ended within ``timeout`` seconds.
        """
        return _poll(lambda: self.run(run_id), FINAL_RUN_STATUSES, "run %s" % run_id, timeout, interval)

    def junit(self, run_id):
        return self.request("GET", "/api/v1/runs/%s/junit" % self._q(run_id), raw=True).decode("utf-8")

    def episodes(self, run_id):
        """The run's stored episodes (a list)."""
        return self.get("/api/v1/runs/%s/episodes" % self._q(run_id)).get("items", [])

    def episode(self, episode_id):
        return self.get("/api/v1/episodes/" + self._q(episode_id))

    def trajectory(self, episode_id):
        return self.get("/api/v1/episodes/%s/trajectory" % self._q(episode_id))

    def series(self, episode_id, name=None):
        return self.get("/api/v1/episodes/%s/series" % self._q(episode_id), name=name)

    def import_runs(self, path):
        """Merge a database of runs (``hrisim merge``'s results, a shard's) into the server's → the runs
        merged, each ``{"id", "added", "present"}``."""
        with open(path, "rb") as database:
            content = database.read()
        reply = self.request("POST", "/api/v1/runs/import", data=content, content_type="application/vnd.sqlite3")
        return reply["runs"]

    def episode_cameras(self, episode_id):
        """The cameras a video of the episode may use (a list, overview first)."""
        return self.get("/api/v1/episodes/%s/cameras" % self._q(episode_id))["cameras"]

    def film_episode(self, episode_id, camera=None, fps=None, width=None, height=None, format=None):
        """Start filming a stored episode on the server (replayed bit for bit) → the video job.

        ``format`` is ``"mp4"`` (H.264, the default) or ``"webm"`` (VP8). Asking again with the same
        options gives the same job.
        """
        body = {k: v for k, v in (("camera", camera), ("fps", fps), ("width", width), ("height", height), ("format", format)) if v is not None}
        return self.post("/api/v1/episodes/%s/videos" % self._q(episode_id), body)

    def video(self, video_id):
        """A video job: its status (queued, filming, done, failed, cancelled) and progress."""
        return self.get("/api/v1/videos/" + self._q(video_id))

    def wait_video(self, video_id, timeout=600.0, interval=0.2):
        """Poll the video job until it has ended → its status. Raises ``TimeoutError`` after ``timeout`` s."""
        return _poll(lambda: self.video(video_id), FINAL_VIDEO_STATUSES, "video %s" % video_id, timeout, interval)

    def download_video(self, video_id, path):
        """Write the finished video to ``path`` → the number of bytes written."""
        content = self.request("GET", "/api/v1/videos/%s/file" % self._q(video_id), raw=True)
        with open(path, "wb") as out:
            out.write(content)
        return len(content)

    def cancel_video(self, video_id):
        """Cancel a video job (if it is filming) and forget it and its file."""
        return self.request("DELETE", "/api/v1/videos/" + self._q(video_id))

    def metrics(self):
        """Every metric's definition: ``{"items": [...], "series": [...]}``."""
        return self.get("/api/v1/metrics")

    def compare(self, a, b):
        return self.get("/api/v1/runs/compare", a=a, b=b)

    # -- robots ------------------------------------------------------------------------------
    def robots(self):
        return self.get("/api/v1/robots")

    def robot(self, name):
        return self.get("/api/v1/robots/" + self._q(name))
