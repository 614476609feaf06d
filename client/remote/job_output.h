// How the remote commands print resources: one line for people, or the API's own JSON
// (proto3 JSON mapping, field names as in the .proto) with --json.
#pragma once

#include <string>

#include <google/protobuf/message.h>

#include "isocorr/util/progress.h"
#include "isocorr/v1/isocorr.pb.h"

namespace isocorr::cli {

std::string to_json(const google::protobuf::Message& message);
std::string describe_job(const v1::Job& job);
std::string describe_mesh(const v1::Mesh& mesh);
Progress progress_of(const v1::Job& job);
// Exit code for a finished (or unfinished) job: SUCCEEDED 0, FAILED 1, CANCELLED 4.
int exit_code_for_job(const v1::Job& job);

}  // namespace isocorr::cli
