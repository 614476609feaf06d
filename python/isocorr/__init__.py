"""isocorr: dense correspondence between nearly isometric triangle meshes.

numpy in, numpy out::

    import isocorr
    V1, F1 = isocorr.read_mesh("cat0.off")
    V2, F2 = isocorr.read_mesh("cat1.off")
    m = isocorr.match((V1, F1), (V2, F2))
    m.forward   # int32 (n1,): the vertex of cat1 each vertex of cat0 matches

A Shape preprocesses a mesh once for several matches::

    cat0, cat1 = isocorr.Shape(V1, F1), isocorr.Shape(V2, F2)
    m = isocorr.match(cat0, cat1, refine_candidates=4)

A map is scored against ground truth as `isocorr eval` scores it::

    score = isocorr.evaluate(V2, F2, m.forward, truth)   # truth: true target vertex per source vertex
    score["d_grd"], score["kim_auc"]

Attributes of the target (colours, weights, labels) are pulled onto the source, at each
vertex's precise point on the target surface::

    faces, weights = isocorr.precise_map((V1, F1), (V2, F2), m.forward)
    colours1 = isocorr.transfer(colours2, (faces, weights), F2)

An isocorr-server is reached with isocorr.Client (python3-grpcio)::

    with isocorr.Client("127.0.0.1:50051") as server:
        result = server.match("cat0.off", "cat1.off")

Settings are keyword arguments named as in isocorr.settings() (the command line's flags
with underscores); a bad one raises ValueError naming it.
"""

from ._isocorr import (Match, Shape, __version__, coverage, evaluate, match, precise_map, read_mesh, read_obj,
                       render_pair, settings, transfer, transfer_uvs, write_mesh, write_obj)

__all__ = [
    "Match", "Shape", "__version__", "coverage", "evaluate", "match", "precise_map", "read_mesh", "read_obj", "render_pair",
    "geodesic_error", "settings", "transfer", "transfer_uvs", "write_mesh", "write_obj",
]


def geodesic_error(V, F, forward, truth):
    """Each source vertex's geodesic error on the target (V, F), over the target's diameter.

    forward and truth hold a target vertex per source vertex (truth -1: unknown). Returns
    float64 (n_source,), NaN where the truth is unknown: the per-point errors whose mean is
    evaluate()'s d_grd, scored at every point.
    """
    import numpy as np

    truth = np.asarray(truth)
    score = evaluate(V, F, forward, truth, max_points=0)
    errors = np.full(len(truth), np.nan)
    errors[score["point_sources"]] = score["point_errors"]
    return errors


def __getattr__(name):
    # The remote client loads grpc only when asked for: the engine alone does not need it.
    if name in ("Client", "RemoteError", "RemoteResult"):
        from . import client

        return getattr(client, name)
    raise AttributeError(f"module 'isocorr' has no attribute {name!r}")
