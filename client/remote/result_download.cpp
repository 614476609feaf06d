#include "remote/result_download.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "codec/result_part_codec.h"
#include "isocorr/output/map_files.h"
#include "isocorr/util/error.h"
#include "remote/rpc_error.h"

namespace isocorr::cli {
namespace {

template <typename T, typename Values>
void append_chunk(std::vector<T>& out, const v1::ResultChunk& chunk, const Values& values) {
  if (chunk.offset() != static_cast<int64_t>(out.size()))
    throw RpcError("download", grpc::Status(grpc::StatusCode::DATA_LOSS, "result chunks arrived out of order"));
  if (out.empty()) out.reserve(static_cast<size_t>(chunk.total()));
  out.insert(out.end(), values.begin(), values.end());
}

// A precise map's points arrive as their faces (indices) and three weights each (values).
void append_points(PreciseMap& out, const v1::ResultChunk& chunk) {
  if (chunk.offset() != static_cast<int64_t>(out.size()) || chunk.values_size() != 3 * chunk.indices_size())
    throw RpcError("download", grpc::Status(grpc::StatusCode::DATA_LOSS, "precise map chunks arrived malformed"));
  if (out.empty()) out.reserve(static_cast<size_t>(chunk.total()));
  for (int i = 0; i < chunk.indices_size(); ++i)
    out.push_back({chunk.indices(i), {chunk.values(3 * i), chunk.values(3 * i + 1), chunk.values(3 * i + 2)}});
}

// A map the server sent must have one entry per vertex of its mesh, each a vertex of the
// other mesh: a corrupted result is refused here rather than written.
// A reverse map may mark target vertices without a counterpart (a part's match).
void check_map(const char* what, const std::vector<int>& map, int64_t vertices, int64_t other_vertices,
               bool may_have_no_counterpart) {
  auto refuse = [&](const std::string& problem) {
    throw RpcError("download", grpc::Status(grpc::StatusCode::DATA_LOSS,
                                            std::string("the server sent a corrupted ") + what + " map (" + problem +
                                                "); nothing written"));
  };
  if (static_cast<int64_t>(map.size()) != vertices)
    refuse(std::to_string(map.size()) + " entries for " + std::to_string(vertices) + " vertices");
  for (size_t i = 0; i < map.size(); ++i)
    if (map[i] >= other_vertices || (map[i] < 0 && !(may_have_no_counterpart && map[i] == kNoCounterpart)))
      refuse("entry " + std::to_string(i) + " is " + std::to_string(map[i]) + ", outside the other mesh's " +
             std::to_string(other_vertices) + " vertices");
}

// One point per vertex, each a face index or -1 with finite weights.
void check_points(const char* what, const PreciseMap& points, int64_t vertices) {
  std::string problem;
  if (static_cast<int64_t>(points.size()) != vertices)
    problem = std::to_string(points.size()) + " points for " + std::to_string(vertices) + " vertices";
  for (size_t i = 0; problem.empty() && i < points.size(); ++i)
    if (points[i].face < -1 || !std::isfinite(points[i].weights[0] + points[i].weights[1] + points[i].weights[2]))
      problem = "point " + std::to_string(i) + " is no point of a face";
  if (!problem.empty())
    throw RpcError("download", grpc::Status(grpc::StatusCode::DATA_LOSS, std::string("the server sent a corrupted ") +
                                                                             what + " map (" + problem + "); nothing written"));
}

}  // namespace

MatchOutput download_result(Connection& connection, const std::string& job_name, const std::vector<ResultPart>& parts) {
  auto context = connection.context(/*long_call=*/true);
  v1::DownloadResultRequest request;
  request.set_name(job_name);
  for (const ResultPart part : parts) request.add_parts(api::result_part_to_proto(part));
  auto reader = connection.jobs().DownloadResult(context.get(), request);
  MatchOutput result;
  std::vector<char> report;
  v1::ResultChunk chunk;
  while (reader->Read(&chunk)) {
    const std::optional<ResultPart> part = api::result_part_from_proto(chunk.part());
    if (!part) continue;  // parts added by a newer server
    switch (*part) {
      case ResultPart::kForwardMap: append_chunk(result.forward, chunk, chunk.indices()); break;
      case ResultPart::kReverseMap: append_chunk(result.reverse, chunk, chunk.indices()); break;
      case ResultPart::kForwardConfidence: append_chunk(result.forward_confidence, chunk, chunk.values()); break;
      case ResultPart::kReverseConfidence: append_chunk(result.reverse_confidence, chunk, chunk.values()); break;
      case ResultPart::kReport: append_chunk(report, chunk, chunk.data()); break;
      case ResultPart::kForwardPrecise: append_points(result.forward_precise, chunk); break;
      case ResultPart::kReversePrecise: append_points(result.reverse_precise, chunk); break;
    }
  }
  check_rpc(reader->Finish(), *context, "cannot download the result of " + job_name);
  result.report_json.assign(report.begin(), report.end());

  v1::GetJobRequest get;
  get.set_name(job_name);
  v1::Job job;
  auto get_context = connection.context();
  check_rpc(connection.jobs().GetJob(get_context.get(), get, &job), *get_context, "cannot read " + job_name);
  const int64_t sources = job.result().source_vertex_count(), targets = job.result().target_vertex_count();
  const bool all = parts.empty();
  auto asked = [&](ResultPart part) { return all || std::find(parts.begin(), parts.end(), part) != parts.end(); };
  if (asked(ResultPart::kForwardMap)) check_map("forward", result.forward, sources, targets, false);
  if (asked(ResultPart::kReverseMap)) check_map("reverse", result.reverse, targets, sources, true);
  if (asked(ResultPart::kForwardPrecise) && !result.forward_precise.empty())
    check_points("forward precise", result.forward_precise, sources);
  if (asked(ResultPart::kReversePrecise) && !result.reverse_precise.empty())
    check_points("reverse precise", result.reverse_precise, targets);
  return result;
}

}  // namespace isocorr::cli
