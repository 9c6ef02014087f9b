-- Issue 23. An upload can be taken out of the catalogue: deleted when no run ran it, else only unlisted
-- (listed = 0), so that the reports and replays of the runs that ran it still find it by id.
ALTER TABLE scenarios ADD COLUMN listed INTEGER NOT NULL DEFAULT 1 CHECK (listed IN (0, 1));
