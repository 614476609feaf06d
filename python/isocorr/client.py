"""isocorr.Client: an isocorr-server from Python, results as numpy arrays.

    with isocorr.Client("127.0.0.1:50051") as server:
        result = server.match("cat0.off", "cat1.off", refine_candidates=4)
        result.forward   # int32, as isocorr.match returns it

Over Debian's python3-grpcio; the API's stubs are generated when the package is built and
ship inside it (isocorr/_proto).
"""

import hashlib
import json
import os
import tempfile
import time

import numpy as np

# The generated stubs import google.rpc and isocorr.v1 by their proto paths; google.rpc is
# not packaged by Debian, so it ships in isocorr/_proto and joins the installed google
# package's path.
_PROTO = os.path.join(os.path.dirname(__file__), "_proto")
import google  # noqa: E402

if os.path.join(_PROTO, "google") not in google.__path__:
    google.__path__.append(os.path.join(_PROTO, "google"))

import grpc  # noqa: E402

from ._isocorr import settings as _settings_table  # noqa: E402
from ._isocorr import write_mesh as _write_mesh  # noqa: E402
from .v1 import isocorr_pb2 as pb  # noqa: E402
from .v1 import isocorr_pb2_grpc as rpc  # noqa: E402

_CHUNK_BYTES = 1 << 20
_WAIT_SLICE_SECONDS = 30


class RemoteError(RuntimeError):
    """A job that failed or was cancelled on the server; `code` is its google.rpc code."""

    def __init__(self, job, code, message):
        super().__init__(f"{job}: {message}")
        self.job, self.code = job, code


class RemoteResult:
    """A finished job's result: forward, reverse (int32), confidence, reverse_confidence
    (float32), precise and reverse_precise ((faces, weights) as isocorr.precise_map gives
    them; None for a result stored before precise maps), report (dict), verdict ('ok' or
    'suspect'; '' for a result stored before verdicts) and verdict_reasons, and the job's
    name and summary."""

    def __init__(self, job, summary, parts):
        self.job, self.summary = job, summary
        self.verdict, self.verdict_reasons = summary.verdict, list(summary.verdict_reasons)
        self.forward = parts.get(pb.FORWARD_MAP)
        self.reverse = parts.get(pb.REVERSE_MAP)
        self.confidence = parts.get(pb.FORWARD_CONFIDENCE)
        self.reverse_confidence = parts.get(pb.REVERSE_CONFIDENCE)
        self.precise = parts.get(pb.FORWARD_PRECISE)
        self.reverse_precise = parts.get(pb.REVERSE_PRECISE)
        report = parts.get(pb.REPORT_JSON)
        self.report = json.loads(report) if report is not None else None

    def __repr__(self):
        return f"<isocorr.RemoteResult of {self.job}: {len(self.forward)} -> {len(self.reverse)} vertices>"


def _settings_message(settings):
    """The API's MatchSettings from keyword settings named as in isocorr.settings()."""
    table = {row["name"]: row for row in _settings_table()}
    message = pb.MatchSettings()
    for name, value in settings.items():
        if name == "landmarks":  # pairs (source vertex, target vertex), beside the table
            for source_vertex, target_vertex in np.asarray(value, dtype=np.int64).reshape(-1, 2):
                message.landmarks.add(source_vertex=int(source_vertex), target_vertex=int(target_vertex))
            continue
        row = table.get(name)
        if row is None:
            raise ValueError(f"unknown setting '{name}' (isocorr.settings() lists them)")
        if row["scope"] == "local":
            raise ValueError(f"{name} is how a process runs, not sent to a server")
        if row["type"] == "choice":
            enum = message.DESCRIPTOR.fields_by_name[name].enum_type
            wanted = str(value).upper().replace("-", "_")
            names = [v.name for v in enum.values if v.name in (wanted, f"{name.upper()}_{wanted}")]
            if not names:
                raise ValueError(f"{name} takes one of {row['choices']}, got {value!r}")
            setattr(message, name, enum.values_by_name[names[0]].number)
        else:
            setattr(message, name, value)
    return message


class Client:
    """A connection to an isocorr-server. `token` is its bearer token; `tls` asks for TLS,
    with `root_certificates` (PEM bytes) to trust a private CA. `timeout` bounds each call
    but the wait for a job."""

    def __init__(self, address, *, token=None, tls=False, root_certificates=None, timeout=60.0):
        if tls or root_certificates:
            credentials = grpc.ssl_channel_credentials(root_certificates=root_certificates)
            self._channel = grpc.secure_channel(address, credentials)
        else:
            self._channel = grpc.insecure_channel(address)
        self._metadata = [("authorization", f"Bearer {token}")] if token else None
        self._timeout = timeout
        self._meshes = rpc.MeshServiceStub(self._channel)
        self._jobs = rpc.JobServiceStub(self._channel)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self._channel.close()

    def upload(self, mesh):
        """Uploads a mesh file (a path) or a (V, F) pair; returns its name, meshes/SHA256."""
        if isinstance(mesh, (str, os.PathLike)):
            with open(mesh, "rb") as file:
                data, filename = file.read(), os.path.basename(os.fspath(mesh))
        else:
            with tempfile.TemporaryDirectory() as folder:
                path = os.path.join(folder, "mesh.off")
                _write_mesh(path, *mesh)
                with open(path, "rb") as file:
                    data, filename = file.read(), "mesh.off"
        header = pb.UploadMeshRequest.Header(sha256=hashlib.sha256(data).hexdigest(), filename=filename,
                                             size_bytes=len(data))

        def requests():
            yield pb.UploadMeshRequest(header=header)
            for start in range(0, len(data), _CHUNK_BYTES):
                yield pb.UploadMeshRequest(chunk=data[start:start + _CHUNK_BYTES])

        response = self._meshes.UploadMesh(requests(), timeout=self._timeout, metadata=self._metadata)
        return response.mesh.name

    def _mesh_name(self, mesh):
        if isinstance(mesh, str) and mesh.startswith("meshes/"):
            return mesh
        return self.upload(mesh)

    def submit(self, source, target, **settings):
        """Creates a match job; source and target are mesh names or what upload() takes.
        Returns the job's name, jobs/ID."""
        request = pb.CreateMatchJobRequest(source_mesh=self._mesh_name(source), target_mesh=self._mesh_name(target),
                                           settings=_settings_message(settings))
        return self._jobs.CreateMatchJob(request, timeout=self._timeout, metadata=self._metadata).name

    def wait(self, job, timeout=None):
        """Waits until the job is done (or `timeout` seconds pass) and returns it (the API's
        Job message)."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            left = _WAIT_SLICE_SECONDS if deadline is None else max(0.0, min(_WAIT_SLICE_SECONDS, deadline - time.monotonic()))
            request = pb.WaitJobRequest(name=job)
            request.timeout.FromNanoseconds(int(left * 1e9))
            answer = self._jobs.WaitJob(request, timeout=left + self._timeout, metadata=self._metadata)
            if answer.done or (deadline is not None and time.monotonic() >= deadline):
                return answer

    def download(self, job):
        """The result of a finished job, every part, as numpy arrays and a dict."""
        answer = self._jobs.GetJob(pb.GetJobRequest(name=job), timeout=self._timeout, metadata=self._metadata)
        if answer.state != pb.Job.SUCCEEDED:
            raise RemoteError(job, answer.error.code, answer.error.message or pb.Job.State.Name(answer.state))
        parts, report = {}, []
        chunks = self._jobs.DownloadResult(pb.DownloadResultRequest(name=job), timeout=self._timeout,
                                           metadata=self._metadata)
        for chunk in chunks:
            if chunk.part in (pb.FORWARD_MAP, pb.REVERSE_MAP):
                array = parts.setdefault(chunk.part, np.empty(chunk.total, dtype=np.int32))
                array[chunk.offset:chunk.offset + len(chunk.indices)] = chunk.indices
            elif chunk.part in (pb.FORWARD_CONFIDENCE, pb.REVERSE_CONFIDENCE):
                array = parts.setdefault(chunk.part, np.empty(chunk.total, dtype=np.float32))
                array[chunk.offset:chunk.offset + len(chunk.values)] = chunk.values
            elif chunk.part in (pb.FORWARD_PRECISE, pb.REVERSE_PRECISE):
                faces, weights = parts.setdefault(
                    chunk.part, (np.empty(chunk.total, dtype=np.int32), np.empty((chunk.total, 3), dtype=np.float32)))
                faces[chunk.offset:chunk.offset + len(chunk.indices)] = chunk.indices
                weights[chunk.offset:chunk.offset + len(chunk.indices)] = np.reshape(chunk.values, (-1, 3))
            else:
                report.append(chunk.data)
        if report:
            parts[pb.REPORT_JSON] = b"".join(report)
        return RemoteResult(job, answer.result, parts)

    def match(self, source, target, *, timeout=None, **settings):
        """Uploads what is not on the server yet, runs the match there and downloads it."""
        job = self.submit(source, target, **settings)
        answer = self.wait(job, timeout)
        if not answer.done:
            raise TimeoutError(f"{job} is not done after {timeout} s")
        return self.download(job)

__all__ = ["Client", "RemoteError", "RemoteResult"]
