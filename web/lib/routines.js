// A scenario's routines (IMHuS's compound tasks) as the pages read them. A scenario written before the
// routine had its name says "tasks" and "task" instead: the server reads those for one version more
// (with a warning), and so do the pages.

/** The scenario's routines: name → actions. */
export function routinesOf(scenario) {
  return scenario.routines ?? scenario.tasks ?? {};
}

/** The routine an action, a request or an entry of async or requests names. */
export function routineOf(entry) {
  return entry.routine ?? entry.task;
}
