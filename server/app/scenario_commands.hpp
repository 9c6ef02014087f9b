#pragma once
// `hrisim validate`, `run`, `import` and `render`: checking a scenario file, running it headless,
// converting XML, and replaying a stored episode to a video.
#include <string>
#include <vector>

namespace hrisim::app {

/// hrisim validate FILE...: prints every error with its JSON pointer; exit 0 when all are valid, 1 if not.
int validate_command(const std::vector<std::string>& args);

/// hrisim run FILE [--seed N | --seeds A-B|A,B,C] [--gate EXPR ...] [--junit FILE] [--db FILE] [--jobs N]
/// [--controller JSON] [--max-time S] [--events] [--request TIME:TASK ...] [--scenario NAME] [--map FILE]
/// [--trajectory FILE.csv]. One plain episode prints its summary (exit 0). With --seeds, --gate, --junit
/// or --db it is a run: episodes on --jobs threads, stored (in --db, or a scratch file), the run report
/// printed; exit 0 when the verdict passes, 1 when a gate fails or an episode did not finish. Exit 2 on
/// bad arguments or an invalid scenario.
int run_command(const std::vector<std::string>& args);

/// hrisim import [--from imhus|pedsim] FILE [--scenario NAME] [--map FILE]: the native JSON on stdout,
/// warnings and errors (with XML lines) on stderr; exit 1 when the file cannot be imported.
int import_command(const std::vector<std::string>& args);

/// hrisim render EPISODE --out FILE.mp4|.webm|.avi [--db FILE] [--camera overview] [--fps 25] [--width W] [--height H]
/// [--scenarios DIR]: runs the stored episode again (same scenario snapshot, seed, controller, time
/// limit and requests: bit for bit the same) and writes what the camera sees to a video; warns when
/// the replay ends otherwise than the stored episode did.
int render_command(const std::vector<std::string>& args);

/// Folder of bundled scenarios and maps searched for relative map names.
std::string bundled_scenarios_dir();

}  // namespace hrisim::app
