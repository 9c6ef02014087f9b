#pragma once
// What a user gives a run — its name, tags and notes — and the checks they pass wherever they come
// from: the REST API (POST /api/v1/runs, PATCH /api/v1/runs/{id}) or an imported database.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace hrisim::runs {

/// Longest run name and notes, most tags and longest tag, in bytes.
inline constexpr std::size_t kMaxRunNameLength = 200;
inline constexpr std::size_t kMaxRunNotesLength = 20000;
inline constexpr std::size_t kMaxRunTags = 32;
inline constexpr std::size_t kMaxRunTagLength = 64;

/// Every problem of a run's labels, as {pointer, message} ("/name", "/notes", "/tags", "/tags/3"):
/// too long, a NUL byte in text, too many tags, a tag that is empty, too long, holds a space or comma,
/// or comes twice.
nlohmann::json label_problems(const std::string& name, const std::vector<std::string>& tags, const std::string& notes);

}  // namespace hrisim::runs
