// Readers for the ground-truth formats of shared/data (see its README for each format).
#include "isocorr/eval/ground_truth.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

namespace fs = std::filesystem;

// One whitespace-separated line of a text file, with its 1-based line number for messages.
struct Line {
  int number;
  std::vector<std::string> tokens;
};

// All non-blank lines of a file (handles CRLF, tabs and leading spaces).
std::vector<Line> read_lines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read ground-truth file " + path);
  std::vector<Line> lines;
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    std::istringstream words(text);
    Line line{number, {}};
    for (std::string w; words >> w;) line.tokens.push_back(w);
    if (!line.tokens.empty()) lines.push_back(std::move(line));
  }
  return lines;
}

[[noreturn]] void fail(const std::string& path, int line, const std::string& what) {
  throw InputError(path + ":" + std::to_string(line) + ": " + what);
}

// An integer token; symmetry files written by MATLAB use float notation (6.1000000e+01),
// so an integral float is accepted too.
long long parse_integer(const std::string& token, const std::string& path, int line) {
  long long value = 0;
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec == std::errc() && ptr == end) return value;
  char* stop = nullptr;
  const double real = std::strtod(token.c_str(), &stop);
  if (stop == token.c_str() + token.size() && std::isfinite(real) && real == std::floor(real) &&
      std::abs(real) < 1e15)
    return static_cast<long long>(real);
  fail(path, line, "expected an integer, found '" + token + "'");
}

// Converts a file index to 0-based and checks it against [0, count).
int checked_index(long long raw, int base, int count, const std::string& path, int line,
                  const char* what) {
  const long long index = raw - base;
  if (index < 0 || index >= count)
    fail(path, line, std::string(what) + " index " + std::to_string(raw) + " outside [" +
                         std::to_string(base) + ", " + std::to_string(count - 1 + base) + "] (" +
                         std::to_string(base) + "-based)");
  return static_cast<int>(index);
}

// Lines too short for their format are rejected before any token is read.
void expect_tokens(const Line& line, size_t minimum, const std::string& path, const char* format) {
  if (line.tokens.size() < minimum)
    fail(path, line.number, std::string("expected '") + format + "'");
}

std::string stem_of(const std::string& path) { return fs::path(path).stem().string(); }

// The dataset folder a mesh belongs to: meshes live in `<dataset>/off*/name.off`.
fs::path dataset_root_of(const std::string& mesh_path) {
  return fs::path(mesh_path).parent_path().parent_path();
}

// TOSCA classes are named by the stem without the pose number: cat0 -> cat.
std::string class_of(const std::string& stem) {
  size_t end = stem.size();
  while (end > 0 && std::isdigit(static_cast<unsigned char>(stem[end - 1]))) --end;
  return stem.substr(0, end);
}

// A 1-based left/right map of a shape with `count` vertices: either one value per vertex
// (one per line, or all on one line as in KIDS sym.txt) or `i j` lines (TOPKIDS). 0 means no
// mirror. Returns 0-based, -1 where unknown.
std::vector<int> read_symmetry_map(const std::string& path, int count) {
  const std::vector<Line> lines = read_lines(path);
  std::vector<int> mirror(count, -1);
  auto set = [&](long long i, long long j, int line) {
    const int from = checked_index(i, 1, count, path, line, "symmetry");
    if (j != 0) mirror[from] = checked_index(j, 1, count, path, line, "symmetry");
  };
  if (lines.size() == 1 && lines[0].tokens.size() > 2) {  // a single row of values
    const Line& row = lines[0];
    if (static_cast<int>(row.tokens.size()) != count)
      fail(path, row.number, "has " + std::to_string(row.tokens.size()) + " values but the mesh has " +
                                 std::to_string(count) + " vertices");
    for (int i = 0; i < count; ++i) set(i + 1, parse_integer(row.tokens[i], path, row.number), row.number);
    return mirror;
  }
  const bool pairs = !lines.empty() && lines[0].tokens.size() >= 2;
  if (!pairs && static_cast<int>(lines.size()) != count)
    throw InputError(path + " has " + std::to_string(lines.size()) + " entries but the mesh has " +
                     std::to_string(count) + " vertices");
  for (size_t k = 0; k < lines.size(); ++k) {
    const Line& l = lines[k];
    if (pairs) {
      expect_tokens(l, 2, path, "i j");
      set(parse_integer(l.tokens[0], path, l.number), parse_integer(l.tokens[1], path, l.number), l.number);
    } else {
      set(static_cast<long long>(k) + 1, parse_integer(l.tokens[0], path, l.number), l.number);
    }
  }
  return mirror;
}

// Dense left/right map for a mesh of `dataset_root`, when the dataset ships one:
// TOSCA `gt/symmetry/<class>.sym`, KIDS `gt/sym.txt`. Sets `source_file` when found.
std::optional<std::vector<int>> dataset_symmetry(const fs::path& dataset_root, const std::string& stem,
                                                 int count, std::string& source_file) {
  for (const fs::path& candidate : {dataset_root / "gt" / "symmetry" / (class_of(stem) + ".sym"),
                                    dataset_root / "gt" / "sym.txt"}) {
    if (fs::is_regular_file(candidate)) {
      source_file = candidate.string();
      return read_symmetry_map(source_file, count);
    }
  }
  return std::nullopt;
}

// One integer per line (`.vts` and index maps), converted to 0-based; -1 kept when allowed.
std::vector<int> read_index_column(const std::string& path, int base, int count, bool allow_missing) {
  std::vector<int> indices;
  for (const Line& l : read_lines(path)) {
    const long long raw = parse_integer(l.tokens[0], path, l.number);
    indices.push_back(allow_missing && raw == -1 ? -1 : checked_index(raw, base, count, path, l.number, "vertex"));
  }
  return indices;
}

void mirror_through(GroundTruth& gt, const std::vector<int>& mirror) {
  gt.mirrored_target.resize(gt.target.size());
  for (size_t k = 0; k < gt.target.size(); ++k) gt.mirrored_target[k] = mirror[gt.target[k]];
}

GroundTruth identity_gt(const fs::path& dataset, const BenchmarkPair& pair, int ns, int nt) {
  if (ns != nt)
    throw InputError("ground truth 'identity' pairs vertex i with vertex i, but the source has " + std::to_string(ns) +
                     " vertices and the target " + std::to_string(nt));
  GroundTruth gt;
  const int n = ns;
  for (int i = 0; i < n; ++i) {
    gt.source.push_back(i);
    gt.target.push_back(i);
  }
  gt.description = "identity: vertex i corresponds to vertex i, " + std::to_string(n) + " pairs";
  std::string sym_file;
  if (auto mirror = dataset_symmetry(dataset, stem_of(pair.target_path), nt, sym_file)) {
    mirror_through(gt, *mirror);
    gt.description += "; symmetric GT from " + sym_file;
  } else {
    gt.description += "; no symmetry map";
  }
  return gt;
}

GroundTruth vts_gt(const BenchmarkPair& pair, int ns, int nt) {
  auto vts_path = [](const std::string& mesh, const std::string& suffix) {
    return (dataset_root_of(mesh) / "corres" / (stem_of(mesh) + suffix)).string();
  };
  const std::string a = vts_path(pair.source_path, ".vts"), b = vts_path(pair.target_path, ".vts");
  GroundTruth gt;
  gt.source = read_index_column(a, 1, ns, false);
  gt.target = read_index_column(b, 1, nt, false);
  if (gt.source.size() != gt.target.size())
    throw InputError(a + " has " + std::to_string(gt.source.size()) + " lines but " + b + " has " +
                     std::to_string(gt.target.size()));
  gt.description = "vts: " + std::to_string(gt.source.size()) + " pairs, line k of " + a +
                   " corresponds to line k of " + b + " (1-based)";
  const std::string sym = vts_path(pair.target_path, ".sym.vts");
  if (fs::is_regular_file(sym)) {
    gt.mirrored_target = read_index_column(sym, 1, nt, false);
    if (gt.mirrored_target.size() != gt.target.size())
      throw InputError(sym + " has " + std::to_string(gt.mirrored_target.size()) + " lines but " + b +
                       " has " + std::to_string(gt.target.size()));
    gt.description += "; symmetric GT from " + sym;
  } else {
    gt.description += "; no symmetric GT";
  }
  return gt;
}

GroundTruth prefix_gt(int ns, int nt) {
  constexpr int kPrefix = 6890;  // the FAUST registration vertices lead every remesh
  if (ns < kPrefix || nt < kPrefix)
    throw InputError("prefix6890 ground truth needs at least 6890 vertices on both meshes (have " +
                     std::to_string(ns) + " and " + std::to_string(nt) + ")");
  GroundTruth gt;
  for (int i = 0; i < kPrefix; ++i) {
    gt.source.push_back(i);
    gt.target.push_back(i);
  }
  gt.description = "prefix6890: vertex i corresponds to vertex i for the 6890 registration vertices; no symmetry map";
  return gt;
}

GroundTruth ref_to_null_gt(const fs::path& dataset, const BenchmarkPair& pair, int ns, int nt) {
  const std::string ref = (dataset / "gt" / (stem_of(pair.source_path) + "_ref.txt")).string();
  GroundTruth gt;
  for (const Line& l : read_lines(ref)) {
    expect_tokens(l, 2, ref, "i j");
    gt.source.push_back(checked_index(parse_integer(l.tokens[0], ref, l.number), 1, ns, ref, l.number, "source"));
    gt.target.push_back(checked_index(parse_integer(l.tokens[1], ref, l.number), 1, nt, ref, l.number, "target"));
  }
  gt.description = "ref_to_null: " + std::to_string(gt.source.size()) + " pairs from " + ref + " (1-based)";
  // The null shape's self-symmetry (kid00_sym.txt) mirrors the targets.
  const std::string sym = (dataset / "gt" / (stem_of(pair.target_path) + "_sym.txt")).string();
  if (fs::is_regular_file(sym)) {
    mirror_through(gt, read_symmetry_map(sym, nt));
    gt.description += "; symmetric GT from " + sym;
  } else {
    gt.description += "; no symmetry map";
  }
  return gt;
}

// Feature points `vid x y z` (0-based vid, -1 = feature absent on this mesh).
std::vector<int> read_feature_points(const std::string& path, int count) {
  std::vector<int> vids;
  for (const Line& l : read_lines(path)) {
    expect_tokens(l, 1, path, "vid x y z");
    const long long raw = parse_integer(l.tokens[0], path, l.number);
    vids.push_back(raw == -1 ? -1 : checked_index(raw, 0, count, path, l.number, "vertex"));
  }
  return vids;
}

GroundTruth sparse_vts_gt(const fs::path& dataset, const BenchmarkPair& pair, int ns, int nt) {
  const std::string a = (dataset / "gt" / (stem_of(pair.source_path) + ".vts")).string();
  const std::string b = (dataset / "gt" / (stem_of(pair.target_path) + ".vts")).string();
  const std::vector<int> fa = read_feature_points(a, ns), fb = read_feature_points(b, nt);
  if (fa.size() != fb.size())
    throw InputError(a + " has " + std::to_string(fa.size()) + " feature points but " + b + " has " +
                     std::to_string(fb.size()));
  // The symmetry of class k (`gt/<k>.sym.info`, k from the protocol `class<k>_...`) swaps
  // feature lines; a single number is a feature on the symmetry axis.
  std::vector<int> swap;
  std::string sym;
  if (pair.protocol.rfind("class", 0) == 0) {
    size_t end = 5;
    while (end < pair.protocol.size() && std::isdigit(static_cast<unsigned char>(pair.protocol[end]))) ++end;
    if (end > 5) sym = (dataset / "gt" / (pair.protocol.substr(5, end - 5) + ".sym.info")).string();
  }
  const bool has_sym = !sym.empty() && fs::is_regular_file(sym);
  if (has_sym) {
    swap.assign(fb.size(), -1);
    for (const Line& l : read_lines(sym)) {
      const int p = checked_index(parse_integer(l.tokens[0], sym, l.number), 0, static_cast<int>(fb.size()), sym,
                                  l.number, "feature");
      const int q = l.tokens.size() < 2 ? p
                                        : checked_index(parse_integer(l.tokens[1], sym, l.number), 0,
                                                        static_cast<int>(fb.size()), sym, l.number, "feature");
      swap[p] = q;
      swap[q] = p;
    }
  }
  GroundTruth gt;
  for (size_t k = 0; k < fa.size(); ++k) {
    if (fa[k] < 0 || fb[k] < 0) continue;  // feature not placed on one of the meshes
    gt.source.push_back(fa[k]);
    gt.target.push_back(fb[k]);
    if (has_sym) gt.mirrored_target.push_back(swap[k] < 0 ? -1 : fb[swap[k]]);
  }
  gt.description = "sparse_vts: " + std::to_string(gt.source.size()) + " feature points, line k of " + a +
                   " corresponds to line k of " + b + " (0-based)";
  gt.description += has_sym ? "; symmetric GT from " + sym : "; no symmetry map";
  return gt;
}

GroundTruth index_map_gt(const fs::path& dataset, const BenchmarkPair& pair, int ns, int nt) {
  const std::string file = (dataset / pair.gt_kind.substr(std::string("index_map:").size())).string();
  const std::vector<int> map = read_index_column(file, 0, nt, true);
  if (static_cast<int>(map.size()) != ns)
    throw InputError(file + " has " + std::to_string(map.size()) + " entries but the source has " +
                     std::to_string(ns) + " vertices");
  GroundTruth gt;
  for (int i = 0; i < ns; ++i)
    if (map[i] >= 0) {
      gt.source.push_back(i);
      gt.target.push_back(map[i]);
    }
  gt.description = "index_map: " + std::to_string(gt.source.size()) + " partial vertices mapped into the full mesh by " +
                   file + " (0-based)";
  // The full mesh is a TOSCA mesh for some pairs: its class symmetry mirrors the targets.
  std::string sym_file;
  if (auto mirror = dataset_symmetry(dataset_root_of(pair.target_path), stem_of(pair.target_path), nt, sym_file)) {
    mirror_through(gt, *mirror);
    gt.description += "; symmetric GT from " + sym_file;
  } else {
    gt.description += "; no symmetry map";
  }
  return gt;
}

}  // namespace

std::vector<BenchmarkPair> read_pairs_tsv(const std::string& dataset_dir) {
  const std::string path = dataset_dir + "/pairs.tsv";
  std::ifstream in(path);
  if (!in) throw InputError("cannot read " + path);
  // Same spelling as the CLI builds (`dir + "/" + relative`), so pairs can be looked up by path.
  auto resolve = [&](const std::string& p) { return fs::path(p).is_absolute() ? p : dataset_dir + "/" + p; };
  std::vector<BenchmarkPair> pairs;
  bool header = true;
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (text.find_first_not_of(" \t") == std::string::npos) continue;
    std::vector<std::string> fields;
    std::istringstream cells(text);
    for (std::string cell; std::getline(cells, cell, '\t');) fields.push_back(cell);
    if (header) {
      if (fields.size() < 4 || fields[0] != "source" || fields[1] != "target" || fields[2] != "gt_kind" ||
          fields[3] != "protocol")
        fail(path, number, "expected the header 'source<TAB>target<TAB>gt_kind<TAB>protocol'");
      header = false;
      continue;
    }
    if (fields.size() < 3 || fields[0].empty() || fields[1].empty() || fields[2].empty())
      fail(path, number, "expected 'source<TAB>target<TAB>gt_kind<TAB>protocol'");
    pairs.push_back({resolve(fields[0]), resolve(fields[1]), fields[2], fields.size() > 3 ? fields[3] : ""});
  }
  if (header) throw InputError(path + " is empty (no header line)");
  return pairs;
}

GroundTruth load_ground_truth(const std::string& dataset_dir, const BenchmarkPair& pair, int source_vertices,
                              int target_vertices) {
  const fs::path dataset(dataset_dir);
  const std::string& kind = pair.gt_kind;
  if (kind == "identity") return identity_gt(dataset, pair, source_vertices, target_vertices);
  if (kind == "vts") return vts_gt(pair, source_vertices, target_vertices);
  if (kind == "prefix6890") return prefix_gt(source_vertices, target_vertices);
  if (kind == "ref_to_null") return ref_to_null_gt(dataset, pair, source_vertices, target_vertices);
  if (kind == "sparse_vts") return sparse_vts_gt(dataset, pair, source_vertices, target_vertices);
  if (kind.rfind("index_map:", 0) == 0 && kind.size() > 10)
    return index_map_gt(dataset, pair, source_vertices, target_vertices);
  throw InputError("unknown ground-truth kind '" + kind +
                   "' (expected identity, vts, prefix6890, ref_to_null, sparse_vts or index_map:<file>)");
}

}  // namespace isocorr
