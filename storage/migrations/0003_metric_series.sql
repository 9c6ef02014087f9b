-- Per-step series of an episode (distance to the closest person, speed, …) for plots, sampled every
-- `stride` ticks from `first_tick`: the values as little-endian float64, NaN where a step has none.
CREATE TABLE metric_series (
  episode_id TEXT NOT NULL REFERENCES episodes (id) ON DELETE CASCADE,
  name       TEXT NOT NULL,
  first_tick INTEGER NOT NULL CHECK (first_tick >= 0),
  stride     INTEGER NOT NULL CHECK (stride > 0),
  vals       BLOB NOT NULL,
  PRIMARY KEY (episode_id, name)
) STRICT, WITHOUT ROWID;
