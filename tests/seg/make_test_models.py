#!/usr/bin/python3
"""Tiny ONNX networks with hand-computable outputs for the pndt_seg tests.

Run with Debian's /usr/bin/python3 (python3-onnx, python3-numpy). Every layer is a 1x1
convolution with fixed weights, a concat, or an average pool, so the C++ tests compute the
expected tensors by hand. Usage: make_test_models.py OUTPUT_DIR
"""
import os
import sys

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

W, H = 16, 12  # panoptic / semantic test frame size


def conv1x1(name, x, weight, bias):
    """1x1 convolution node with its initializers (OpenCV 4.6 needs kernel_shape)."""
    w = numpy_helper.from_array(np.asarray(weight, np.float32).reshape(len(weight), -1, 1, 1), name + "_w")
    b = numpy_helper.from_array(np.asarray(bias, np.float32), name + "_b")
    node = helper.make_node("Conv", [x, name + "_w", name + "_b"], [name], kernel_shape=[1, 1], name=name)
    return node, [w, b]


def save(graph, path):
    model = helper.make_model(graph, producer_name="pndt-tests", opset_imports=[helper.make_opsetid("", 11)])
    model.ir_version = 7
    onnx.checker.check_model(model)
    tmp = path + ".tmp"
    onnx.save(model, tmp)
    os.replace(tmp, path)


# Semantic logits over [void, wall, chair, table] from x = [r, g, b, depth] (normalised inputs):
# void = 0.5, wall = 4r, chair = 4g, table = 4b.
SEMANTIC_W = [[0, 0, 0, 0], [4, 0, 0, 0], [0, 4, 0, 0], [0, 0, 4, 0]]
SEMANTIC_B = [0.5, 0, 0, 0]
# Centre heatmap = the normalised depth channel; offsets (dy, dx) = (0, 0.5) everywhere.
CENTER_W, CENTER_B = [[0, 0, 0, 1]], [0]
OFFSET_W, OFFSET_B = [[0, 0, 0, 0], [0, 0, 0, 0]], [0, 0.5]


def rgbd_inputs(w, h):
    return [helper.make_tensor_value_info("rgb", TensorProto.FLOAT, [1, 3, h, w]),
            helper.make_tensor_value_info("depth", TensorProto.FLOAT, [1, 1, h, w])]


def panoptic(path, w, h, semantic_channels=4):
    concat = helper.make_node("Concat", ["rgb", "depth"], ["x"], axis=1, name="x")
    sem, sem_init = conv1x1("semantic", "x", SEMANTIC_W[:semantic_channels], SEMANTIC_B[:semantic_channels])
    cen, cen_init = conv1x1("center", "x", CENTER_W, CENTER_B)
    off, off_init = conv1x1("offset", "x", OFFSET_W, OFFSET_B)
    outputs = [helper.make_tensor_value_info("semantic", TensorProto.FLOAT, [1, semantic_channels, h, w]),
               helper.make_tensor_value_info("center", TensorProto.FLOAT, [1, 1, h, w]),
               helper.make_tensor_value_info("offset", TensorProto.FLOAT, [1, 2, h, w])]
    graph = helper.make_graph([concat, sem, cen, off], "panoptic_tiny", rgbd_inputs(w, h), outputs,
                              sem_init + cen_init + off_init)
    save(graph, path)


def semantic(path, w, h):
    concat = helper.make_node("Concat", ["rgb", "depth"], ["x"], axis=1, name="x")
    sem, sem_init = conv1x1("semantic", "x", SEMANTIC_W, SEMANTIC_B)
    outputs = [helper.make_tensor_value_info("semantic", TensorProto.FLOAT, [1, 4, h, w])]
    save(helper.make_graph([concat, sem], "semantic_tiny", rgbd_inputs(w, h), outputs, sem_init), path)


def detector(path):
    """16x16 RGB input, stride 4: heatmap[c] = 4x4 average of channel c (classes chair, couch,
    dining table); box_size = (l, t, r, b) = (4, 4, 4, 4) input pixels everywhere."""
    pool = helper.make_node("AveragePool", ["rgb"], ["heatmap"], kernel_shape=[4, 4], strides=[4, 4], name="heatmap")
    box, box_init = conv1x1("box_size", "heatmap", [[0, 0, 0]] * 4, [4, 4, 4, 4])
    inputs = [helper.make_tensor_value_info("rgb", TensorProto.FLOAT, [1, 3, 16, 16])]
    outputs = [helper.make_tensor_value_info("heatmap", TensorProto.FLOAT, [1, 3, 4, 4]),
               helper.make_tensor_value_info("box_size", TensorProto.FLOAT, [1, 4, 4, 4])]
    save(helper.make_graph([pool, box], "detector_tiny", inputs, outputs, box_init), path)


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    panoptic(os.path.join(out, "panoptic_tiny.onnx"), W, H)
    panoptic(os.path.join(out, "panoptic_tiny_half.onnx"), W // 2, H // 2)
    panoptic(os.path.join(out, "panoptic_3_channels.onnx"), W, H, semantic_channels=3)
    semantic(os.path.join(out, "semantic_tiny.onnx"), W, H)
    detector(os.path.join(out, "detector_tiny.onnx"))


if __name__ == "__main__":
    main()
