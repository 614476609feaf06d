"""Matches two meshes with isocorr and scores the map against a ground truth.

    python match_and_score.py SOURCE TARGET TRUTH [OUT.npy]

TRUTH is a text file with the true target vertex of each source vertex, one per line (as
`isocorr-make-examples` writes gt/creature_to_moved.txt). Prints the figures `isocorr eval`
prints and writes the map as a NumPy array.
"""

import sys

import numpy as np

import isocorr


def main(source_path, target_path, truth_path, out_path="map.npy"):
    source = isocorr.read_mesh(source_path)
    target = isocorr.read_mesh(target_path)
    m = isocorr.match(source, target, progress=lambda stage, fraction: print(f"  {stage} {fraction:.0%}"))
    np.save(out_path, m.forward)
    truth = np.loadtxt(truth_path, dtype=np.int64)
    score = isocorr.evaluate(*target, m.forward, truth)
    print(f"{len(m.forward)} -> {len(m.reverse)} vertices, D_iso {m.diso:.4f}")
    print(f"D_grd {score['d_grd']:.4f}, Kim AUC {score['kim_auc']:.3f}, flip-free {score['flip_free']}")
    print(f"map written to {out_path}")


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    main(*sys.argv[1:])
