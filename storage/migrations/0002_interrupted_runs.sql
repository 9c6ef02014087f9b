-- A run can end 'interrupted': the server stopped while it ran (its finished episodes stay). SQLite
-- cannot change a CHECK constraint in place, so the table is rebuilt; migrations run with foreign keys
-- off, so dropping the old table leaves the episodes alone.
CREATE TABLE runs_new (
  id          TEXT PRIMARY KEY,
  scenario_id TEXT NOT NULL REFERENCES scenarios (id),
  controller  TEXT NOT NULL,
  config      TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(config)),
  status      TEXT NOT NULL CHECK (status IN ('queued', 'running', 'finished', 'failed', 'cancelled', 'interrupted')),
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
  finished_at TEXT
) STRICT;
INSERT INTO runs_new (id, scenario_id, controller, config, status, created_at, finished_at)
  SELECT id, scenario_id, controller, config, status, created_at, finished_at FROM runs ORDER BY rowid;
DROP TABLE runs;
ALTER TABLE runs_new RENAME TO runs;
CREATE INDEX runs_by_scenario ON runs (scenario_id);
CREATE INDEX runs_by_status ON runs (status);
