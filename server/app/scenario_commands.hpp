#pragma once
// `hrisim validate`, `import` and `render`: checking a scenario file, converting another simulator's
// file (or upgrading an older hrisim one), and replaying a stored episode to a video.
#include <string>
#include <vector>

namespace hrisim::app {

/// hrisim validate FILE...: prints every error with its JSON pointer; exit 0 when all are valid, 1 if not.
int validate_command(const std::vector<std::string>& args);

/// hrisim import [--from imhus|pedsim] FILE [--scenario NAME] [--map FILE]: the native JSON on stdout,
/// warnings and errors (with XML lines) on stderr; exit 1 when the file cannot be imported.
/// hrisim import --upgrade FILE [--in-place]: a hrisim scenario with its keys' former names renamed
/// (former_keys.hpp), on stdout or into the file, each key renamed said on stderr; exit 1 for a file
/// that is not JSON or has a key under both its names.
int import_command(const std::vector<std::string>& args);

/// hrisim render EPISODE --out FILE.mp4|.webm|.avi [--db FILE] [--camera overview] [--fps 25] [--width W] [--height H]
/// [--scenarios DIR]: runs the stored episode again (same scenario snapshot, seed, controller, time
/// limit and requests: bit for bit the same) and writes what the camera sees to a video; warns when
/// the replay ends otherwise than the stored episode did.
int render_command(const std::vector<std::string>& args);

}  // namespace hrisim::app
