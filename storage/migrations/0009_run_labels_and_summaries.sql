-- Issue 23. A run has a name, tags and notes its user gives (and edits), and, once it has ended, the
-- summary of its report (each metric's aggregate, as the report gives it) that lists sort and filter by.
ALTER TABLE runs ADD COLUMN name TEXT NOT NULL DEFAULT '';
ALTER TABLE runs ADD COLUMN tags TEXT NOT NULL DEFAULT '[]' CHECK (json_valid(tags) AND json_type(tags) = 'array');
ALTER TABLE runs ADD COLUMN notes TEXT NOT NULL DEFAULT '';
ALTER TABLE runs ADD COLUMN summary TEXT CHECK (summary IS NULL OR json_valid(summary));
