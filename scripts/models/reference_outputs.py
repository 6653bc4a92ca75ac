#!/usr/bin/python3
"""Runs the original TF.js graph (NumPy reference, NHWC, original weights) on DIR/input.npy
(the NCHW float32 blob our front-end feeds the ONNX network) and writes DIR/heatmap.npy and
DIR/box_size.npy in NCHW, for `pndt-seg-bench --check-reference DIR` to compare OpenCV DNN's
outputs of the converted network against.

Usage: reference_outputs.py MODEL.json DIR [--input tower_0/images] [--output heatmap=tower_0/keypoints ...]
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import reference_tfjs  # noqa: E402
from tfjs_graph import GraphModel  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("model_json")
    ap.add_argument("dir")
    ap.add_argument("--input", default="tower_0/images")
    ap.add_argument("--output", action="append", default=[])
    a = ap.parse_args()
    outputs = [o.split("=", 1) for o in (a.output or ["heatmap=tower_0/keypoints", "box_size=tower_0/wh"])]
    g = GraphModel(a.model_json)
    x = np.load(os.path.join(a.dir, "input.npy")).astype(np.float32)
    if x.ndim != 4:
        sys.exit(f"reference_outputs: {a.dir}/input.npy must be NCHW (got shape {x.shape})")
    values = reference_tfjs.run(g, [t for _, t in outputs], {a.input: x.transpose(0, 2, 3, 1)})
    for (name, _), v in zip(outputs, values):
        np.save(os.path.join(a.dir, name + ".npy"), np.ascontiguousarray(v.transpose(0, 3, 1, 2)))
        print(f"reference_outputs: {name} {list(v.shape)} (NHWC) max {float(v.max()):.4f}")


if __name__ == "__main__":
    main()
