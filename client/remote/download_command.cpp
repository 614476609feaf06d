// `isocorr download JOB -o MAP ...`: writes a finished job's maps, confidences and report.
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "isocorr/output/map_files.h"
#include "isocorr/output/precise_map_files.h"
#include "isocorr/util/error.h"
#include "remote/job_follow.h"
#include "remote/remote_subcommand.h"
#include "remote/result_download.h"

namespace isocorr::cli {
namespace {

struct DownloadArguments {
  std::string name, output, reverse_output, report, confidence, reverse_confidence, precise, reverse_precise;
};

}  // namespace

void register_download_command(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  auto args = std::make_shared<DownloadArguments>();
  CLI::App* cmd = add_remote_command(
      app, "download", "write a finished job's maps, confidences and report", options, exit_code,
      [args](Connection& connection, bool json) {
        const DownloadArguments& d = *args;
        std::vector<ResultPart> parts;
        if (!d.output.empty()) parts.push_back(ResultPart::kForwardMap);
        if (!d.reverse_output.empty()) parts.push_back(ResultPart::kReverseMap);
        if (!d.confidence.empty()) parts.push_back(ResultPart::kForwardConfidence);
        if (!d.reverse_confidence.empty()) parts.push_back(ResultPart::kReverseConfidence);
        if (!d.report.empty()) parts.push_back(ResultPart::kReport);
        if (!d.precise.empty()) parts.push_back(ResultPart::kForwardPrecise);
        if (!d.reverse_precise.empty()) parts.push_back(ResultPart::kReversePrecise);
        if (parts.empty())
          throw InputError("nothing to download: give -o, --reverse-out, --confidence-out, --precise-out or --report");
        const MatchOutput result = download_result(connection, job_name(d.name), parts);
        if (!d.output.empty()) write_map(d.output, result.forward);
        if (!d.reverse_output.empty()) write_map(d.reverse_output, result.reverse);
        if (!d.confidence.empty()) write_values(d.confidence, result.forward_confidence);
        if (!d.reverse_confidence.empty()) write_values(d.reverse_confidence, result.reverse_confidence);
        if (!d.report.empty()) std::ofstream(d.report) << result.report_json << '\n';
        if (!d.precise.empty()) write_precise_map(d.precise, result.forward_precise);
        if (!d.reverse_precise.empty()) write_precise_map(d.reverse_precise, result.reverse_precise);
        if (json)
          print_line("{\"forward_vertices\":" + std::to_string(result.forward.size()) +
                     ",\"reverse_vertices\":" + std::to_string(result.reverse.size()) + "}");
        else
          spdlog::info("downloaded the result of {}", job_name(d.name));
        return kExitOk;
      });
  cmd->add_option("job", args->name, "jobs/ID or ID")->required();
  cmd->add_option("-o,--output", args->output, "forward map (binary if it ends in .bin, NumPy if .npy)");
  cmd->add_option("--reverse-out", args->reverse_output, "target-to-source map");
  cmd->add_option("--confidence-out", args->confidence, "confidence of each forward pair, one per line (NumPy float32 if it ends in .npy)");
  cmd->add_option("--reverse-confidence-out", args->reverse_confidence, "the same for the reverse map");
  cmd->add_option("--report", args->report, "the JSON report");
  cmd->add_option("--precise-out", args->precise,
                  "the precise map: per source vertex a target face and its corners' weights (NumPy (N, 4) if .npy)");
  cmd->add_option("--reverse-precise-out", args->reverse_precise, "the same for the reverse map");
}

}  // namespace isocorr::cli
