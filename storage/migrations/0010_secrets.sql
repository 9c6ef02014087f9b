-- Secrets of this database, each made at random when first asked for (Store::secret). "import_ids"
-- keys the ids an import derives for its owner's copy of a run whose id another owner holds
-- (runs::merge_database), so that no one else can compute them in advance and take them.
CREATE TABLE secrets (
  name  TEXT PRIMARY KEY,
  value TEXT NOT NULL
) STRICT;
