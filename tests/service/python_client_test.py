#!/usr/bin/python3
"""Drives isocorr-server from Python's gRPC (Debian's python3-grpcio), an implementation
independent of the C++ client: stubs are generated here from the project's .proto, and
the server's reflection service is asked which services it offers.

Usage: python_client_test.py --server HOST:PORT --mesh SOURCE --target TARGET --work DIR --proto-path DIR...
Exit 0 when every check passes; prints what failed otherwise.
"""
import argparse
import hashlib
import importlib
import os
import subprocess
import sys


def generate_stubs(work, proto_paths):
    protos = ["isocorr/v1/isocorr.proto", "google/rpc/status.proto", "grpc/health/v1/health.proto",
              "grpc/reflection/v1alpha/reflection.proto"]
    includes = [f"-I{p}" for p in proto_paths]
    subprocess.run(["protoc", *includes, f"--python_out={work}", f"--grpc_out={work}",
                    "--plugin=protoc-gen-grpc=/usr/bin/grpc_python_plugin", *protos], check=True)
    # The generated google.rpc and grpc.health/reflection modules join the installed
    # google and grpc packages rather than shadowing them.
    import google.protobuf  # noqa: F401
    import grpc
    import google
    google.__path__.append(os.path.join(work, "google"))
    grpc.__path__.append(os.path.join(work, "grpc"))
    sys.path.append(work)


def parse_arguments(*extra):
    """--server, --work and --proto-path, plus the required `extra` options; stubs generated."""
    parser = argparse.ArgumentParser()
    for option in ("--server", "--work", *extra):
        parser.add_argument(option, required=True)
    parser.add_argument("--proto-path", action="append", required=True)
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    generate_stubs(args.work, args.proto_path)
    return args


def exit_now(code):
    """Ends the process at once, skipping grpcio's clean-up (channel close, interpreter
    exit), which is known to deadlock now and then: the probe once hung for a CI run's
    whole ten minutes. The kernel closes the sockets."""
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


def main():
    args = parse_arguments("--mesh", "--target")

    import grpc
    pb = importlib.import_module("isocorr.v1.isocorr_pb2")
    rpc = importlib.import_module("isocorr.v1.isocorr_pb2_grpc")
    health_pb = importlib.import_module("grpc.health.v1.health_pb2")
    health_rpc = importlib.import_module("grpc.health.v1.health_pb2_grpc")
    reflection_pb = importlib.import_module("grpc.reflection.v1alpha.reflection_pb2")
    reflection_rpc = importlib.import_module("grpc.reflection.v1alpha.reflection_pb2_grpc")

    failures = []

    def check(condition, what):
        if not condition:
            failures.append(what)

    channel = grpc.insecure_channel(args.server)
    grpc.channel_ready_future(channel).result(timeout=30)

    health = health_rpc.HealthStub(channel).Check(health_pb.HealthCheckRequest(), timeout=10)
    check(health.status == health_pb.HealthCheckResponse.SERVING, "health is not SERVING")

    reflection = reflection_rpc.ServerReflectionStub(channel)
    answers = reflection.ServerReflectionInfo(iter([reflection_pb.ServerReflectionRequest(list_services="")]),
                                              timeout=10)
    services = {s.name for a in answers for s in a.list_services_response.service}
    check({"isocorr.v1.MeshService", "isocorr.v1.JobService"} <= services, f"reflection lists {services}")

    def upload(path):
        data = open(path, "rb").read()
        digest = hashlib.sha256(data).hexdigest()
        yield pb.UploadMeshRequest(header=pb.UploadMeshRequest.Header(
            sha256=digest, filename=os.path.basename(path), size_bytes=len(data)))
        for offset in range(0, len(data), 64 * 1024):
            yield pb.UploadMeshRequest(chunk=data[offset:offset + 64 * 1024])

    meshes = rpc.MeshServiceStub(channel)
    mesh = meshes.UploadMesh(upload(args.mesh), timeout=60).mesh
    digest = hashlib.sha256(open(args.mesh, "rb").read()).hexdigest()
    check(mesh.name == "meshes/" + digest, f"mesh name {mesh.name}")
    target = meshes.UploadMesh(upload(args.target), timeout=60).mesh
    check(meshes.UploadMesh(upload(args.target), timeout=60).already_existed, "second upload was not a no-op")

    def lying_upload():
        data = open(args.mesh, "rb").read()
        yield pb.UploadMeshRequest(header=pb.UploadMeshRequest.Header(sha256="0" * 64, filename="x.ply",
                                                                      size_bytes=len(data)))
        yield pb.UploadMeshRequest(chunk=data)

    try:
        meshes.UploadMesh(lying_upload(), timeout=60)
        failures.append("an upload whose bytes do not match its digest was accepted")
    except grpc.RpcError as error:
        check(error.code() == grpc.StatusCode.INVALID_ARGUMENT and "hashes to" in error.details(),
              f"digest mismatch gave {error.code()} {error.details()}")

    jobs = rpc.JobServiceStub(channel)
    job = jobs.CreateMatchJob(pb.CreateMatchJobRequest(source_mesh=mesh.name, target_mesh=target.name), timeout=10)
    check(job.state == pb.Job.QUEUED and not job.done, f"new job is {pb.Job.State.Name(job.state)}")
    last = None
    for last in jobs.WatchJob(pb.WatchJobRequest(name=job.name), timeout=600):
        pass
    check(last is not None and last.done and last.state == pb.Job.SUCCEEDED, f"job ended {last}")

    chunks = list(jobs.DownloadResult(pb.DownloadResultRequest(name=job.name, parts=[pb.FORWARD_MAP]), timeout=60))
    forward = [i for c in chunks for i in c.indices]
    check(len(forward) == mesh.vertex_count, f"forward map has {len(forward)} entries")

    try:
        jobs.GetJob(pb.GetJobRequest(name="jobs/0000000000000000"), timeout=10)
        failures.append("GetJob of an unknown job succeeded")
    except grpc.RpcError as error:
        check(error.code() == grpc.StatusCode.NOT_FOUND, f"unknown job gave {error.code()}")
        error_ids = [value for key, value in error.trailing_metadata() if key == "x-request-id"]
        check(len(error_ids) == 1 and error_ids[0].startswith("r"), f"error's request id: {error_ids}")

    # Every response names the server's request in its metadata (here the initial metadata).
    _, call = jobs.GetJob.with_call(pb.GetJobRequest(name=job.name), timeout=10)
    ok_ids = [value for key, value in call.initial_metadata() if key == "x-request-id"]
    check(len(ok_ids) == 1 and ok_ids[0].startswith("r"), f"response's request id: {ok_ids}")

    for failure in failures:
        print("FAILED:", failure)
    exit_now(1 if failures else 0)


if __name__ == "__main__":
    main()
