"""isocorr.Client against a real isocorr-server on loopback: the remote result is the
local one, and bad requests are refused before or by the server with their reason."""

import os
import signal
import socket
import subprocess
import time

import grpc
import numpy as np
import pytest

import isocorr

from conftest import BUILD


def free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    binary = BUILD / "server" / "isocorr-server"
    if not binary.exists():
        pytest.skip(f"no isocorr-server at {binary} (built with the service only)")
    address = f"127.0.0.1:{free_port()}"
    log = open(tmp_path_factory.mktemp("server") / "server.log", "w")
    process = subprocess.Popen([str(binary), "--listen", address, "--data-dir",
                                str(tmp_path_factory.mktemp("data")), "--threads", "1"], stdout=log, stderr=log)
    channel = grpc.insecure_channel(address)
    try:
        grpc.channel_ready_future(channel).result(timeout=60)
    finally:
        channel.close()
    yield address
    process.send_signal(signal.SIGTERM)
    try:
        process.wait(timeout=30)
    except subprocess.TimeoutExpired:
        process.kill()
    log.close()


def test_a_remote_match_is_the_local_one(server, examples):
    source, target = examples / "meshes" / "creature.ply", examples / "meshes" / "creature_moved.ply"
    local = isocorr.match(isocorr.read_mesh(str(source)), isocorr.read_mesh(str(target)))
    with isocorr.Client(server) as client:
        remote = client.match(source, target)
    assert remote.forward.dtype == np.int32 and np.array_equal(remote.forward, local.forward)
    assert np.array_equal(remote.reverse, local.reverse)
    assert remote.confidence.dtype == np.float32 and np.array_equal(remote.confidence, local.confidence)
    assert remote.report["final"]["diso"] == local.report["final"]["diso"]
    assert remote.summary.source_vertex_count == len(local.forward)
    assert remote.verdict == local.verdict and remote.verdict_reasons == local.verdict_reasons
    for remote_part, local_part in ((remote.precise, local.precise), (remote.reverse_precise, local.reverse_precise)):
        assert np.array_equal(remote_part[0], local_part[0]) and np.array_equal(remote_part[1], local_part[1])


def test_arrays_upload_as_a_mesh_and_settings_travel(server, examples):
    V, F = isocorr.read_mesh(str(examples / "meshes" / "creature.ply"))
    with isocorr.Client(server) as client:
        name = client.upload((V, F))
        assert name.startswith("meshes/") and client.upload((V, F)) == name
        moved = client.upload(examples / "meshes" / "creature_moved.ply")
        result = client.match(name, moved, refine="none", min_tracked=8, landmarks=[[0, 5]])
    assert result.report["settings"]["refine"] == "none" and result.report["settings"]["min_tracked"] == 8
    assert result.report["landmarks"]["count"] == 1 and result.forward[0] == 5


def test_bad_requests_are_refused_with_their_reason(server, examples):
    with isocorr.Client(server) as client:
        with pytest.raises(ValueError, match="unknown setting 'no_such'"):
            client.submit("meshes/" + "0" * 64, "meshes/" + "0" * 64, no_such=1)
        with pytest.raises(ValueError, match="threads is how a process runs"):
            client.submit("meshes/" + "0" * 64, "meshes/" + "0" * 64, threads=2)
        with pytest.raises(grpc.RpcError) as refused:
            client.submit("meshes/" + "0" * 64, "meshes/" + "0" * 64)
        assert refused.value.code() == grpc.StatusCode.NOT_FOUND
