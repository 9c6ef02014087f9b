#include "humans/recorded_trajectories.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <string_view>
#include <unordered_set>

#include "core/error.hpp"

namespace hrisim::humans {
namespace {

/// The longest line a row may be: four numbers and their separators (the real files' longest is 43).
constexpr std::size_t kMaxLineLength = 200;
/// The largest |x| or |y|, m: a camera's scene is far smaller, and squared distances stay finite.
constexpr double kMaxCoordinate = 1e5;
/// The largest |frame| or |person| taken as a whole number: doubles are exact integers up to 2^53.
constexpr double kMaxWholeNumber = 9e15;

struct Row {
  long long person = 0;
  RecordedSample sample;
  std::size_t line = 0;
};

[[noreturn]] void fail(const std::string& source, std::size_t line, const std::string& message) {
  throw core::Error(core::ErrorCode::bad_request, source + ":" + std::to_string(line) + ": " + message, "line",
                    std::to_string(line));
}

std::vector<std::string_view> fields_of(std::string_view text) {
  std::vector<std::string_view> fields;
  constexpr std::string_view kSeparators = " \t\r";
  std::size_t begin = text.find_first_not_of(kSeparators);
  while (begin != std::string_view::npos) {
    const std::size_t end = std::min(text.find_first_of(kSeparators, begin), text.size());
    fields.push_back(text.substr(begin, end - begin));
    begin = text.find_first_not_of(kSeparators, end);
  }
  return fields;
}

/// The row on one line; `line` is its number for the errors.
Row parse_row(std::string_view text, const std::string& source, std::size_t line) {
  const std::vector<std::string_view> fields = fields_of(text);
  if (fields.size() != 4) {
    fail(source, line, "expected 4 fields (frame, person, x, y), found " + std::to_string(fields.size()));
  }
  static constexpr std::array<const char*, 4> kNames = {"frame", "person", "x", "y"};
  std::array<double, 4> values{};
  for (std::size_t k = 0; k < 4; ++k) {
    const std::string_view field = fields[k];
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), values[k]);
    if (ec != std::errc() || end != field.data() + field.size() || !std::isfinite(values[k])) {
      fail(source, line, std::string(kNames[k]) + " '" + std::string(field) + "' is not a number");
    }
    const bool whole = k < 2;
    if (whole && (values[k] != std::floor(values[k]) || std::abs(values[k]) > kMaxWholeNumber)) {
      fail(source, line, std::string(kNames[k]) + " '" + std::string(field) + "' is not a whole number");
    }
    if (!whole && std::abs(values[k]) > kMaxCoordinate) {
      fail(source, line, std::string(kNames[k]) + " " + std::string(field) + " m is farther than " +
                             std::to_string(static_cast<long long>(kMaxCoordinate)) + " m from the origin");
    }
  }
  return {static_cast<long long>(values[1]), {static_cast<long long>(values[0]), Vec2(values[2], values[3])}, line};
}

/// Rows ordered by person, then frame, grouped into tracks; a person seen twice in a frame is an error.
RecordedTrajectories tracks_of(std::vector<Row> rows, const std::string& source) {
  std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) {
    return a.person != b.person ? a.person < b.person : a.sample.frame < b.sample.frame;
  });
  RecordedTrajectories trajectories;
  trajectories.rows = rows.size();
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& row = rows[k];
    if (k > 0 && rows[k - 1].person == row.person && rows[k - 1].sample.frame == row.sample.frame) {
      // Stable: the earlier row in the file comes first.
      fail(source, row.line, "person " + std::to_string(row.person) + " is in frame " + std::to_string(row.sample.frame) +
                                 " twice (also at line " + std::to_string(rows[k - 1].line) + ")");
    }
    if (trajectories.tracks.empty() || trajectories.tracks.back().person != row.person) {
      trajectories.tracks.push_back({row.person, {}});
    }
    trajectories.tracks.back().samples.push_back(row.sample);
  }
  return trajectories;
}

}  // namespace

RecordedTrajectories read_eth_ucy(std::istream& input, const std::string& source, const RecordedLimits& limits) {
  std::vector<Row> rows;
  std::unordered_set<long long> people;
  long long first_frame = 0, last_frame = 0;
  std::array<char, kMaxLineLength + 1> buffer{};  // getline keeps one place for its terminating zero
  for (std::size_t line = 1;; ++line) {
    input.getline(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    if (input.bad()) fail(source, line, "cannot be read");
    const bool ended = input.eof();
    if (input.fail()) {
      if (ended && input.gcount() == 0) break;  // nothing after the last newline
      fail(source, line, "longer than " + std::to_string(kMaxLineLength) + " characters: not a row of four numbers");
    }
    // gcount counts the newline it took off, but not a final line's missing one.
    const auto length = static_cast<std::size_t>(input.gcount()) - (ended ? 0 : 1);
    const std::string_view text(buffer.data(), length);
    if (text.find_first_not_of(" \t\r") != std::string_view::npos) {
      if (rows.size() == limits.max_rows) fail(source, line, "more than " + std::to_string(limits.max_rows) + " rows");
      const Row row = parse_row(text, source, line);
      if (people.insert(row.person).second && people.size() > limits.max_people) {
        fail(source, line, "more than " + std::to_string(limits.max_people) + " people");
      }
      first_frame = rows.empty() ? row.sample.frame : std::min(first_frame, row.sample.frame);
      last_frame = rows.empty() ? row.sample.frame : std::max(last_frame, row.sample.frame);
      if (last_frame - first_frame > limits.max_frame_span) {
        fail(source, line, "frames " + std::to_string(first_frame) + " to " + std::to_string(last_frame) + " span more than " +
                               std::to_string(limits.max_frame_span));
      }
      rows.push_back(row);
    }
    if (ended) break;
  }
  return tracks_of(std::move(rows), source);
}

}  // namespace hrisim::humans
