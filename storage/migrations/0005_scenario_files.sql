-- Issue 17. Files uploaded alongside a scenario (a ROS map's YAML and image, an IMHuS world), named
-- by their path relative to the scenario as its references name them; they are compiled with it and
-- nothing else on the server's disk can be named by an upload.
CREATE TABLE scenario_files (
  scenario_id TEXT NOT NULL REFERENCES scenarios (id) ON DELETE CASCADE,
  path        TEXT NOT NULL,
  content     BLOB NOT NULL,
  PRIMARY KEY (scenario_id, path)
) WITHOUT ROWID;
