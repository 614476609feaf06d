#include "landmarks_file.h"

#include <charconv>
#include <fstream>
#include <sstream>

#include "isocorr/transfer/landmarks.h"
#include "isocorr/util/error.h"

namespace isocorr::cli {
namespace {

InputError file_error(const std::string& path, int line, const std::string& problem) {
  return InputError("landmarks file '" + path + "'" + (line > 0 ? " line " + std::to_string(line) : "") + ": " +
                    problem);
}

// A vertex index as written: a whole number that fits 32 bits.
bool parse_vertex(const std::string& word, int& vertex) {
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), vertex);
  return error == std::errc() && end == word.data() + word.size();
}

void throw_first_problem(const LandmarksFile& file, const std::vector<Landmark>& landmarks, int source_vertices,
                         int target_vertices) {
  const auto problem = find_landmark_problem(landmarks, source_vertices, target_vertices);
  if (!problem) return;
  // Past the limit there is no line of its own to name.
  const int line = problem->index < file.lines.size() ? file.lines[problem->index] : 0;
  throw file_error(file.path, line,
                   problem->message +
                       (problem->earlier ? " (line " + std::to_string(file.lines[*problem->earlier]) + ")" : ""));
}

}  // namespace

void read_landmarks_file(const std::string& path, std::vector<Landmark>& landmarks, LandmarksFile& file) {
  std::ifstream in(path);
  if (!in) throw file_error(path, 0, "cannot be read");
  file = LandmarksFile{path, {}};
  landmarks.clear();
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    text = text.substr(0, text.find('#'));
    std::istringstream words(text);
    std::vector<std::string> fields;
    for (std::string word; words >> word;) fields.push_back(word);
    if (fields.empty()) continue;
    Landmark l;
    if (fields.size() != 2 || !parse_vertex(fields[0], l.source_vertex) || !parse_vertex(fields[1], l.target_vertex))
      throw file_error(path, line, "expected 'source_vertex target_vertex' (two whole numbers), got '" +
                                       text.substr(0, 60) + "'");
    landmarks.push_back(l);
    file.lines.push_back(line);
  }
  if (in.bad()) throw file_error(path, 0, "cannot be read");
  throw_first_problem(file, landmarks, -1, -1);
}

void check_landmarks_fit(const LandmarksFile& file, const std::vector<Landmark>& landmarks, int source_vertices,
                         int target_vertices) {
  if (file.path.empty()) return;
  throw_first_problem(file, landmarks, source_vertices, target_vertices);
}

}  // namespace isocorr::cli
