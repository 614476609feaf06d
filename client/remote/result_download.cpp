#include "remote/result_download.h"

#include <cstdio>
#include <fstream>

#include "codec/result_part_codec.h"
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
    }
  }
  check_rpc(reader->Finish(), "cannot download the result of " + job_name);
  result.report_json.assign(report.begin(), report.end());
  return result;
}

void write_values_text(const std::string& path, const std::vector<float>& values) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) throw InputError("cannot write '" + path + "'");
  for (const float value : values) std::fprintf(file, "%.6g\n", value);
  if (std::fclose(file) != 0) throw InputError("cannot write '" + path + "'");
}

}  // namespace isocorr::cli
