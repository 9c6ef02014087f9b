-- Issue 17. A scenario keeps the summary a list shows, so listing never compiles it; scenarios and
-- runs carry their owner (the name of the token that made them, '' without owners); a run records the
-- process that computes it (pid, the boot id and the start time of the process), so one whose process died is found
-- interrupted by whoever opens the database next, and one a live process still runs is left alone.
ALTER TABLE scenarios ADD COLUMN summary TEXT CHECK (summary IS NULL OR json_valid(summary));
ALTER TABLE scenarios ADD COLUMN owner TEXT NOT NULL DEFAULT '';
ALTER TABLE runs ADD COLUMN owner TEXT NOT NULL DEFAULT '';
ALTER TABLE runs ADD COLUMN process_id INTEGER;
ALTER TABLE runs ADD COLUMN process_identity TEXT;
CREATE INDEX scenarios_by_owner ON scenarios (owner, id);
CREATE INDEX runs_by_owner ON runs (owner);
