#!/usr/bin/python3
"""Asks a server's reflection service (grpc.reflection.v1alpha) two questions without a
token, list_services and file_containing_symbol, and prints one line per question: the
service or file names answered, or the gRPC status code of the refusal.

Usage: reflection_probe.py --server HOST:PORT --work DIR --proto-path DIR...
"""
import importlib

from python_client_test import exit_now, parse_arguments


def main():
    args = parse_arguments()
    import grpc
    reflection_pb = importlib.import_module("grpc.reflection.v1alpha.reflection_pb2")
    reflection_rpc = importlib.import_module("grpc.reflection.v1alpha.reflection_pb2_grpc")
    channel = grpc.insecure_channel(args.server)
    stub = reflection_rpc.ServerReflectionStub(channel)
    questions = [("list_services", reflection_pb.ServerReflectionRequest(list_services="")),
                 ("file_containing_symbol",
                  reflection_pb.ServerReflectionRequest(file_containing_symbol="isocorr.v1.MeshService"))]
    for label, question in questions:
        try:
            answers = list(stub.ServerReflectionInfo(iter([question]), timeout=10))
            names = [s.name for a in answers for s in a.list_services_response.service]
            files = [len(a.file_descriptor_response.file_descriptor_proto) for a in answers]
            print(f"{label}: answered {' '.join(names)} {sum(files)} file(s)")
        except grpc.RpcError as error:
            print(f"{label}: {error.code().name}")
    exit_now(0)


if __name__ == "__main__":
    main()
