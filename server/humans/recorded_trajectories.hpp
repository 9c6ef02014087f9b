#pragma once
// Real pedestrians' recorded tracks in ETH/UCY's four-column text (frame, person, x, y in metres, one
// row per person and frame, as the Social-GAN and Trajectron++ releases of these sets have them).
#include <cstddef>
#include <istream>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace hrisim::humans {

using core::Vec2;

/// Frames between two annotations in ETH/UCY's text files (their 2.5 Hz annotation numbered on the
/// 25 Hz video, Social-GAN's and Trajectron++'s releases): one annotation every 0.4 s.
inline constexpr int kEthUcyFrameStep = 10;
/// Time between two annotations, s (Pellegrini et al. 2009 and Lerner et al. 2007 annotated at 2.5 Hz).
inline constexpr double kEthUcyFrameInterval = 0.4;

/// How much a file may expand to. The ETH and ZARA01 test sets have 5,492 and 5,153 rows, 360 and
/// 148 people, and span 11,600 and 9,010 frames; the bounds leave room for sets forty times larger
/// while keeping the evaluation of one file (rows × simulated steps) to minutes.
struct RecordedLimits {
  std::size_t max_rows = 200'000;
  std::size_t max_people = 10'000;
  long long max_frame_span = 1'000'000;  ///< last frame minus first: 11 hours of 25 Hz video
};

/// A person seen at one annotated frame.
struct RecordedSample {
  long long frame = 0;
  Vec2 position = Vec2::Zero();
};

/// One person's samples, frames ascending (gaps where they were not annotated).
struct RecordedTrack {
  long long person = 0;
  std::vector<RecordedSample> samples;
};

/// A file's people, ordered by their ids.
struct RecordedTrajectories {
  std::vector<RecordedTrack> tracks;
  std::size_t rows = 0;
};

/// Reads ETH/UCY's four columns separated by spaces or tabs; blank lines are skipped. Frame and person
/// are whole numbers (written `780` or `780.0`), x and y finite. Throws core::Error(bad_request) naming
/// `source` and the line: a field that is not a number, a row without exactly four fields, a person
/// seen twice in one frame, a line longer than a row can be, or a file past `limits`.
RecordedTrajectories read_eth_ucy(std::istream& input, const std::string& source, const RecordedLimits& limits = {});

}  // namespace hrisim::humans
