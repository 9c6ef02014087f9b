-- Issue 18. The hash of the episode's final state (16 hex digits), so that a stored episode can be
-- checked against the same seed driven another way (a session, a realtime session, a replay). Episodes
-- stored before this migration have none.
ALTER TABLE episodes ADD COLUMN state_hash TEXT;
