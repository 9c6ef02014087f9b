-- Issue 21. A scenario may come as a HuNavSim agents file (format 'hunav_yaml'). SQLite cannot change a
-- CHECK constraint in place, so the table is rebuilt with the columns later migrations added; migrations
-- run with foreign keys off, so dropping the old table leaves the runs and files that refer to it alone.
CREATE TABLE scenarios_new (
  id          TEXT PRIMARY KEY,
  name        TEXT NOT NULL,
  format      TEXT NOT NULL CHECK (format IN ('json', 'imhus_xml', 'pedsim_xml', 'hunav_yaml')),
  source      TEXT NOT NULL,
  sha256      TEXT NOT NULL CHECK (length(sha256) = 64),
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
  summary     TEXT CHECK (summary IS NULL OR json_valid(summary)),
  owner       TEXT NOT NULL DEFAULT ''
) STRICT;
INSERT INTO scenarios_new (id, name, format, source, sha256, created_at, summary, owner)
  SELECT id, name, format, source, sha256, created_at, summary, owner FROM scenarios ORDER BY rowid;
DROP TABLE scenarios;
ALTER TABLE scenarios_new RENAME TO scenarios;
CREATE INDEX scenarios_by_hash ON scenarios (sha256);
CREATE INDEX scenarios_by_owner ON scenarios (owner, id);
