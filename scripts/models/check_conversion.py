#!/usr/bin/python3
"""Independent check of a TF.js -> ONNX conversion (scripts/models/tfjs_to_onnx.py).

Two separate NumPy interpreters, one per format, share no code with the converter (nor with
scripts/models/tfjs_graph.py):
  * the ORIGINAL TF.js graph model (model.json + .bin shards, float16/float32/uint8 weights) is
    evaluated in its own NHWC layout with its own weights and TensorFlow's padding rules;
  * the converted ONNX file (read with the onnx package, weights from its initializers) is
    evaluated in NCHW following the ONNX operator definitions.
Both run on the same image; the outputs must agree (max abs difference of the heatmap below
--tol, of box_size below --box-tol). The top detections (3x3 local maxima of the heatmap, boxes
scaled to the image's pixels) are printed so a person can judge the class order.

Images: .jpg (baseline JPEG, decoded by the small NumPy decoder below, since Debian's
/usr/bin/python3 here has no image library; Pillow is used when importable), binary .ppm, .npy
(H x W x 3 uint8 RGB, or an NCHW float32 blob of the network's input size). Without --image a
fixed pseudo-random image is used. The image is stretched to the network input with bilinear
interpolation (half-pixel centres, like cv::resize INTER_LINEAR); the exact input blob is saved.

--save-reference FILE.npz writes the first image's input blob ("input", NCHW float32, RGB 0..255)
and the TF.js graph's outputs ("heatmap", "box_size", NCHW float32) for the C++ test to compare
OpenCV DNN against; --save-reference-dir DIR writes the same as DIR/input.npy, heatmap.npy,
box_size.npy (the layout `pndt-model-check --check-reference DIR` reads).

Usage: check_conversion.py MODEL.json MODEL.onnx [--description centernet_coco.json]
       [--image IMG]... [--tol 1e-3] [--box-tol 0.05] [--save-reference F.npz] [--top 10]
Exit status: 0 agreement, 1 disagreement, 2 usage / input error.
"""
import argparse
import base64
import json
import os
import sys
import time

import numpy as np

# ----------------------------------------------------------------------------------------------
# TF.js graph model: reader and NHWC interpreter
# ----------------------------------------------------------------------------------------------

NP_DTYPES = {"float32": np.float32, "float16": np.float16, "int32": np.int32, "uint8": np.uint8,
             "uint16": np.uint16, "bool": np.bool_}


class TfjsModel:
    def __init__(self, path):
        with open(path) as f:
            doc = json.load(f)
        if "modelTopology" not in doc or "weightsManifest" not in doc:
            raise ValueError(f"{path} is not a TF.js graph model (no modelTopology / weightsManifest)")
        self.nodes = {}
        for n in doc["modelTopology"]["node"]:
            self.nodes[n["name"]] = n
        self.weights = {}
        base = os.path.dirname(os.path.abspath(path))
        for group in doc["weightsManifest"]:
            blob = bytearray()
            for shard in group["paths"]:
                with open(os.path.join(base, shard), "rb") as f:
                    blob += f.read()
            pos = 0
            for w in group["weights"]:
                q = w.get("quantization")
                stored = q["dtype"] if q else w["dtype"]
                n = 1
                for d in w["shape"]:
                    n *= int(d)
                item = np.dtype(NP_DTYPES[stored]).itemsize
                if pos + n * item > len(blob):
                    raise ValueError(f"weights end early at {w['name']}")
                a = np.frombuffer(bytes(blob[pos:pos + n * item]), dtype=NP_DTYPES[stored]).reshape(
                    [int(d) for d in w["shape"]])
                pos += n * item
                if q and stored in ("uint8", "uint16"):
                    a = a.astype(np.float32) * np.float32(q["scale"]) + np.float32(q["min"])
                self.weights[w["name"]] = a.astype(NP_DTYPES[w["dtype"]])
            if pos != len(blob):
                raise ValueError(f"weight shards of {path} have {len(blob) - pos} unused bytes")

    def attr(self, node, key, default=None):
        a = node.get("attr", {}).get(key)
        if a is None:
            return default
        for k in ("s", "i", "f", "b"):
            if k in a:
                v = a[k]
                return {"s": lambda x: base64.b64decode(x).decode(), "i": int, "f": float, "b": bool}[k](v)
        if "list" in a:
            lst = a["list"]
            if "i" in lst:
                return [int(x) for x in lst["i"]]
            if "s" in lst:
                return [base64.b64decode(x).decode() for x in lst["s"]]
            if "f" in lst:
                return [float(x) for x in lst["f"]]
            return []
        return a

    def run(self, feeds, outputs):
        env = dict(feeds)
        env_const = self.weights

        def get(ref):
            name = ref[:-2] if ref.endswith(":0") else ref
            if ":" in name:
                raise ValueError(f"second outputs ({ref}) are not supported by this check")
            if name in env:
                return env[name]
            if name in env_const:
                return env_const[name]
            env[name] = self.eval_node(self.nodes[name], get)
            return env[name]

        # Iterative evaluation (no deep recursion): resolve inputs first.
        for out in outputs:
            stack = [out]
            while stack:
                name = stack[-1]
                if name in env or name in env_const:
                    stack.pop()
                    continue
                node = self.nodes[name]
                missing = [i.split(":")[0] for i in node.get("input", []) if not i.startswith("^")
                           and i.split(":")[0] not in env and i.split(":")[0] not in env_const]
                if missing:
                    stack.extend(missing)
                    continue
                stack.pop()
                env[name] = self.eval_node(node, get)
        return [env[o] for o in outputs]

    def eval_node(self, node, get):
        op = node["op"]
        ins = [get(i) for i in node.get("input", []) if not i.startswith("^")]
        a = lambda k, d=None: self.attr(node, k, d)  # noqa: E731
        if op == "Placeholder":
            raise ValueError(f"placeholder {node['name']} not fed")
        if op == "Const":
            raise ValueError(f"constant {node['name']} has no weights")
        if op in ("Conv2D", "_FusedConv2D", "DepthwiseConv2dNative", "FusedDepthwiseConv2dNative"):
            y = tf_conv(ins[0], ins[1], a("strides", [1, 1, 1, 1]), a("padding"), a("dilations", [1, 1, 1, 1]),
                        "Depthwise" in op)
            fused = a("fused_ops", []) if op in ("_FusedConv2D", "FusedDepthwiseConv2dNative") else []
            for k, f in enumerate(fused):
                if f == "BiasAdd":
                    y = y + ins[2]
                elif f == "FusedBatchNorm":
                    scale, offset, mean, var = ins[2:6]
                    y = (y - mean) * (scale / np.sqrt(var + np.float32(a("epsilon", 0.0)))) + offset
                else:
                    y = tf_activation(f, y, a("leakyrelu_alpha", 0.2))
            return y.astype(np.float32)
        if op == "Conv2DBackpropInput":
            return tf_conv_transpose(ins[2], ins[1], [int(v) for v in ins[0]], a("strides"), a("padding"))
        if op in ("Add", "AddV2", "BiasAdd"):
            return (ins[0] + ins[1]).astype(np.float32)
        if op == "Sub":
            return (ins[0] - ins[1]).astype(np.float32)
        if op == "Mul":
            return (ins[0] * ins[1]).astype(np.float32)
        if op in ("Relu", "Relu6", "Sigmoid", "Tanh", "Elu"):
            return tf_activation(op, ins[0])
        if op == "Identity":
            return ins[0]
        if op in ("FusedBatchNorm", "FusedBatchNormV3"):
            x, scale, offset, mean, var = ins[:5]
            return ((x - mean) * (scale / np.sqrt(var + np.float32(a("epsilon", 0.001)))) + offset).astype(np.float32)
        if op == "Mean":
            axes = tuple(int(v) for v in np.atleast_1d(ins[1]))
            return np.mean(ins[0], axis=axes, keepdims=bool(a("keep_dims", False)), dtype=np.float64).astype(np.float32)
        if op == "ConcatV2":
            return np.concatenate(ins[:-1], axis=int(ins[-1]))
        if op == "Reshape":
            return ins[0].reshape([int(v) for v in ins[1]])
        if op in ("MaxPool", "AvgPool"):
            return tf_pool(ins[0], a("ksize"), a("strides"), a("padding"), op == "MaxPool")
        if op == "ResizeBilinear":
            if a("align_corners", False) or a("half_pixel_centers", False):
                raise ValueError("ResizeBilinear with align_corners / half_pixel_centers is not implemented")
            return tf_resize_bilinear_legacy(ins[0], int(ins[1][0]), int(ins[1][1]))
        raise ValueError(f"TF.js op {op} ({node['name']}) is not implemented in this check")


def tf_activation(f, y, alpha=0.2):
    if f == "Relu":
        return np.maximum(y, 0).astype(np.float32)
    if f == "Relu6":
        return np.minimum(np.maximum(y, 0), 6).astype(np.float32)
    if f == "Sigmoid":
        return (1.0 / (1.0 + np.exp(-y.astype(np.float64)))).astype(np.float32)
    if f == "Tanh":
        return np.tanh(y).astype(np.float32)
    if f == "Elu":
        return np.where(y > 0, y, np.expm1(np.minimum(y, 0))).astype(np.float32)
    if f == "LeakyRelu":
        return np.where(y > 0, y, alpha * y).astype(np.float32)
    raise ValueError(f"TF.js activation {f} is not implemented in this check")


def tf_padding(size, k, s, d, padding):
    """TensorFlow's rule: SAME -> output ceil(size / s), padding total split with the extra at the end."""
    ke = (k - 1) * d + 1
    if padding == "VALID":
        return 0, 0, (size - ke) // s + 1
    if padding != "SAME":
        raise ValueError(f"padding {padding} is not implemented in this check")
    out = (size + s - 1) // s
    total = max(0, (out - 1) * s + ke - size)
    return total // 2, total - total // 2, out


def tf_conv(x, w, strides, padding, dilations, depthwise):
    """NHWC convolution, filter [kh, kw, in, out] or depthwise [kh, kw, C, 1]; loops over the filter taps."""
    n, h, wd, c = x.shape
    kh, kw = w.shape[:2]
    sh, sw = strides[1], strides[2]
    dh, dw = dilations[1], dilations[2]
    t, b, oh = tf_padding(h, kh, sh, dh, padding)
    l, r, ow = tf_padding(wd, kw, sw, dw, padding)
    xp = np.zeros((n, h + t + b, wd + l + r, c), np.float32)
    xp[:, t:t + h, l:l + wd, :] = x
    w = w.astype(np.float32)
    acc = np.zeros((n, oh, ow, c if depthwise else w.shape[3]), np.float64)
    for i in range(kh):
        for j in range(kw):
            tap = xp[:, i * dh:i * dh + sh * (oh - 1) + 1:sh, j * dw:j * dw + sw * (ow - 1) + 1:sw, :]
            if depthwise:
                acc += tap * w[i, j, :, 0]
            else:
                acc += np.tensordot(tap, w[i, j], axes=([3], [0]))
    return acc.astype(np.float32)


def tf_conv_transpose(x, w, out_shape, strides, padding):
    """Gradient of a conv wrt its input: scatter every input pixel through the filter [kh, kw, out, in]."""
    n, h, wd, _ = x.shape
    kh, kw = w.shape[:2]
    sh, sw = strides[1], strides[2]
    t, _, _ = tf_padding(out_shape[1], kh, sh, 1, padding)
    l, _, _ = tf_padding(out_shape[2], kw, sw, 1, padding)
    big = np.zeros((n, out_shape[1] + kh + sh * h, out_shape[2] + kw + sw * wd, w.shape[2]), np.float64)
    for i in range(kh):
        for j in range(kw):
            big[:, i:i + sh * h:sh, j:j + sw * wd:sw, :] += np.tensordot(x, w[i, j], axes=([3], [1]))
    return big[:, t:t + out_shape[1], l:l + out_shape[2], :].astype(np.float32)


def tf_pool(x, ksize, strides, padding, is_max):
    n, h, wd, c = x.shape
    t, b, oh = tf_padding(h, ksize[1], strides[1], 1, padding)
    l, r, ow = tf_padding(wd, ksize[2], strides[2], 1, padding)
    fill = -np.inf if is_max else 0.0
    xp = np.full((n, h + t + b, wd + l + r, c), fill, np.float64)
    xp[:, t:t + h, l:l + wd] = x
    valid = np.zeros((1, h + t + b, wd + l + r, 1))
    valid[:, t:t + h, l:l + wd] = 1
    acc = np.full((n, oh, ow, c), fill)
    cnt = np.zeros((1, oh, ow, 1))
    for i in range(ksize[1]):
        for j in range(ksize[2]):
            sl = (slice(None), slice(i, i + strides[1] * (oh - 1) + 1, strides[1]),
                  slice(j, j + strides[2] * (ow - 1) + 1, strides[2]))
            if is_max:
                acc = np.maximum(acc, xp[sl])
            else:
                acc = acc + xp[sl]
                cnt = cnt + valid[sl]
    return (acc if is_max else acc / cnt).astype(np.float32)


def tf_resize_bilinear_legacy(x, oh, ow):
    """tf.image.resize_bilinear, align_corners = half_pixel_centers = false: src = dst * in / out."""
    _, h, w, _ = x.shape
    ys = np.arange(oh, dtype=np.float64) * (h / oh)
    xs = np.arange(ow, dtype=np.float64) * (w / ow)
    y0 = np.floor(ys).astype(int)
    x0 = np.floor(xs).astype(int)
    y1 = np.minimum(y0 + 1, h - 1)
    x1 = np.minimum(x0 + 1, w - 1)
    wy = (ys - y0)[None, :, None, None]
    wx = (xs - x0)[None, None, :, None]
    xd = x.astype(np.float64)
    top = xd[:, y0][:, :, x0] * (1 - wx) + xd[:, y0][:, :, x1] * wx
    bottom = xd[:, y1][:, :, x0] * (1 - wx) + xd[:, y1][:, :, x1] * wx
    return (top * (1 - wy) + bottom * wy).astype(np.float32)


# ----------------------------------------------------------------------------------------------
# ONNX: NCHW interpreter of the operators the converter may write
# ----------------------------------------------------------------------------------------------

def run_onnx(path, feeds):
    import onnx
    from onnx import numpy_helper

    model = onnx.load(path)
    g = model.graph
    env = {t.name: numpy_helper.to_array(t) for t in g.initializer}
    env.update(feeds)
    for node in g.node:  # ONNX requires topological node order
        attrs = {a.name: onnx.helper.get_attribute_value(a) for a in node.attribute}
        ins = [env[i] if i else None for i in node.input]
        out = onnx_op(node.op_type, ins, attrs, node.name)
        env[node.output[0]] = out
    return {o.name: env[o.name] for o in g.output}


def onnx_op(op, ins, at, name):
    x = ins[0]
    if op == "Conv":
        return onnx_conv(x, ins[1], ins[2] if len(ins) > 2 else None, at)
    if op == "ConvTranspose":
        return onnx_conv_transpose(x, ins[1], ins[2] if len(ins) > 2 else None, at)
    if op in ("Add", "Sub", "Mul", "Div", "Min", "Max"):
        f = {"Add": np.add, "Sub": np.subtract, "Mul": np.multiply, "Div": np.divide,
             "Min": np.minimum, "Max": np.maximum}[op]
        y = ins[0]
        for other in ins[1:]:
            y = f(y, other)
        return y.astype(np.float32)
    if op == "Relu":
        return np.where(x > 0, x, 0).astype(np.float32)
    if op == "Sigmoid":
        return (1.0 / (1.0 + np.exp(-x.astype(np.float64)))).astype(np.float32)
    if op == "Tanh":
        return np.tanh(x).astype(np.float32)
    if op == "Elu":
        return np.where(x > 0, x, at.get("alpha", 1.0) * np.expm1(np.minimum(x, 0))).astype(np.float32)
    if op == "LeakyRelu":
        return np.where(x > 0, x, at.get("alpha", 0.01) * x).astype(np.float32)
    if op == "Clip":
        lo = ins[1] if len(ins) > 1 and ins[1] is not None else at.get("min", -np.inf)
        hi = ins[2] if len(ins) > 2 and ins[2] is not None else at.get("max", np.inf)
        return np.clip(x, lo, hi).astype(np.float32)
    if op == "Identity":
        return x
    if op == "GlobalAveragePool":
        return x.mean(axis=(2, 3), keepdims=True, dtype=np.float64).astype(np.float32)
    if op in ("MaxPool", "AveragePool"):
        return onnx_pool(x, at, op == "MaxPool")
    if op == "Concat":
        return np.concatenate(ins, axis=at["axis"])
    if op == "Reshape":
        shape = [int(v) for v in ins[1]]
        shape = [x.shape[i] if v == 0 else v for i, v in enumerate(shape)]
        return x.reshape(shape)
    if op == "Slice":  # opset 10+: starts, ends, [axes], [steps] as inputs
        starts, ends = [int(v) for v in ins[1]], [int(v) for v in ins[2]]
        axes = [int(v) for v in ins[3]] if len(ins) > 3 and ins[3] is not None else list(range(len(starts)))
        steps = [int(v) for v in ins[4]] if len(ins) > 4 and ins[4] is not None else [1] * len(starts)
        sl = [slice(None)] * x.ndim
        for st, en, ax, sp in zip(starts, ends, axes, steps):
            sl[ax] = slice(st, min(en, x.shape[ax]) if en >= 0 else en, sp)
        return x[tuple(sl)]
    if op == "Transpose":
        return np.transpose(x, at.get("perm"))
    if op == "Resize":
        return onnx_resize(x, ins, at)
    raise ValueError(f"ONNX op {op} ({name}) is not implemented in this check")


def onnx_conv(x, w, b, at):
    """Conv by im2col: a [N, C*kh*kw, OH*OW] patch matrix per group times the [O, C*kh*kw] weights."""
    n, c, h, wd = x.shape
    o, cg, kh, kw = w.shape
    ks = at.get("kernel_shape", [kh, kw])
    if list(ks) != [kh, kw]:
        raise ValueError("Conv kernel_shape disagrees with the weights")
    group = at.get("group", 1)
    sh, sw = at.get("strides", [1, 1])
    dh, dw = at.get("dilations", [1, 1])
    pt, pl, pb, pr = at.get("pads", [0, 0, 0, 0])
    if at.get("auto_pad", b"NOTSET") not in (b"NOTSET", "NOTSET"):
        raise ValueError("Conv auto_pad is not implemented in this check")
    xp = np.pad(x, ((0, 0), (0, 0), (pt, pb), (pl, pr)))
    oh = (h + pt + pb - (dh * (kh - 1) + 1)) // sh + 1
    ow = (wd + pl + pr - (dw * (kw - 1) + 1)) // sw + 1
    og = o // group
    out = np.empty((n, o, oh, ow), np.float32)
    if group == c and cg == 1 and og == 1:  # depthwise: per-channel products, summed over taps
        acc = np.zeros((n, c, oh, ow), np.float64)
        for i in range(kh):
            for j in range(kw):
                acc += xp[:, :, i * dh:i * dh + sh * (oh - 1) + 1:sh, j * dw:j * dw + sw * (ow - 1) + 1:sw] * \
                    w[:, 0, i, j][None, :, None, None]
        out[:] = acc
    else:
        for gi in range(group):
            xs = xp[:, gi * cg:(gi + 1) * cg]
            cols = np.empty((n, cg, kh, kw, oh, ow), np.float32)
            for i in range(kh):
                for j in range(kw):
                    cols[:, :, i, j] = xs[:, :, i * dh:i * dh + sh * (oh - 1) + 1:sh, j * dw:j * dw + sw * (ow - 1) + 1:sw]
            wm = w[gi * og:(gi + 1) * og].reshape(og, -1).astype(np.float64)
            res = np.einsum("ok,nkp->nop", wm, cols.reshape(n, cg * kh * kw, oh * ow).astype(np.float64))
            out[:, gi * og:(gi + 1) * og] = res.reshape(n, og, oh, ow)
    if b is not None:
        out += b.reshape(1, -1, 1, 1)
    return out


def onnx_conv_transpose(x, w, b, at):
    n, c, h, wd = x.shape
    _, o, kh, kw = w.shape
    if at.get("group", 1) != 1:
        raise ValueError("grouped ConvTranspose is not implemented in this check")
    sh, sw = at.get("strides", [1, 1])
    pt, pl, pb, pr = at.get("pads", [0, 0, 0, 0])
    oph, opw = at.get("output_padding", [0, 0])
    full_h, full_w = (h - 1) * sh + kh, (wd - 1) * sw + kw
    full = np.zeros((n, o, full_h + oph, full_w + opw), np.float64)
    for i in range(kh):
        for j in range(kw):
            full[:, :, i:i + sh * (h - 1) + 1:sh, j:j + sw * (wd - 1) + 1:sw] += np.einsum("nchw,co->nohw", x, w[:, :, i, j])
    y = full[:, :, pt:full_h + oph - pb, pl:full_w + opw - pr]
    if b is not None:
        y = y + b.reshape(1, -1, 1, 1)
    return y.astype(np.float32)


def onnx_pool(x, at, is_max):
    n, c, h, wd = x.shape
    kh, kw = at["kernel_shape"]
    sh, sw = at.get("strides", [1, 1])
    pt, pl, pb, pr = at.get("pads", [0, 0, 0, 0])
    oh = (h + pt + pb - kh) // sh + 1
    ow = (wd + pl + pr - kw) // sw + 1
    fill = -np.inf if is_max else 0.0
    xp = np.pad(x.astype(np.float64), ((0, 0), (0, 0), (pt, pb), (pl, pr)), constant_values=fill)
    ones = np.pad(np.ones((h, wd)), ((pt, pb), (pl, pr)))
    acc = np.full((n, c, oh, ow), fill)
    cnt = np.zeros((oh, ow))
    for i in range(kh):
        for j in range(kw):
            sl = (slice(i, i + sh * (oh - 1) + 1, sh), slice(j, j + sw * (ow - 1) + 1, sw))
            acc = np.maximum(acc, xp[(..., *sl)]) if is_max else acc + xp[(..., *sl)]
            cnt += ones[sl]
    if not is_max:
        acc = acc / (cnt if not at.get("count_include_pad", 0) else kh * kw)
    return acc.astype(np.float32)


def onnx_resize(x, ins, at):
    mode = at.get("mode", b"nearest")
    mode = mode.decode() if isinstance(mode, bytes) else mode
    ctm = at.get("coordinate_transformation_mode", b"half_pixel")
    ctm = ctm.decode() if isinstance(ctm, bytes) else ctm
    scales = ins[2] if len(ins) > 2 and ins[2] is not None and ins[2].size else None
    sizes = ins[3] if len(ins) > 3 and ins[3] is not None else None
    if sizes is not None:
        out = [int(v) for v in sizes]
        scales = np.array(out, np.float64) / np.array(x.shape, np.float64)
    else:
        out = [int(np.floor(d * s)) for d, s in zip(x.shape, scales)]
    if list(out[:2]) != list(x.shape[:2]):
        raise ValueError("Resize over batch/channels is not implemented in this check")

    def coords(o_len, i_len, scale):
        d = np.arange(o_len, dtype=np.float64)
        if ctm == "asymmetric":
            return d / scale
        if ctm == "half_pixel":
            return (d + 0.5) / scale - 0.5
        if ctm == "pytorch_half_pixel":
            return (d + 0.5) / scale - 0.5 if o_len > 1 else np.zeros(o_len)
        if ctm == "align_corners":
            return d * (i_len - 1) / (o_len - 1) if o_len > 1 else np.zeros(o_len)
        raise ValueError(f"Resize coordinate_transformation_mode {ctm} is not implemented in this check")

    ys = coords(out[2], x.shape[2], float(scales[2]))
    xs = coords(out[3], x.shape[3], float(scales[3]))
    if mode == "nearest":
        yi = np.clip(np.floor(ys).astype(int), 0, x.shape[2] - 1)
        xi = np.clip(np.floor(xs).astype(int), 0, x.shape[3] - 1)
        return x[:, :, yi][:, :, :, xi]
    if mode != "linear":
        raise ValueError(f"Resize mode {mode} is not implemented in this check")
    ys = np.clip(ys, 0, x.shape[2] - 1)
    xs = np.clip(xs, 0, x.shape[3] - 1)
    y0 = np.floor(ys).astype(int)
    x0 = np.floor(xs).astype(int)
    y1 = np.minimum(y0 + 1, x.shape[2] - 1)
    x1 = np.minimum(x0 + 1, x.shape[3] - 1)
    fy = (ys - y0)[:, None]
    fx = (xs - x0)[None, :]
    xd = x.astype(np.float64)
    rows0, rows1 = xd[:, :, y0], xd[:, :, y1]
    top = rows0[..., x0] * (1 - fx) + rows0[..., x1] * fx
    bottom = rows1[..., x0] * (1 - fx) + rows1[..., x1] * fx
    return (top * (1 - fy) + bottom * fy).astype(np.float32)


# ----------------------------------------------------------------------------------------------
# Images
# ----------------------------------------------------------------------------------------------

ZIGZAG = np.array([
    0, 1, 8, 16, 9, 2, 3, 10, 17, 24, 32, 25, 18, 11, 4, 5, 12, 19, 26, 33, 40, 48, 41, 34, 27, 20, 13, 6, 7, 14,
    21, 28, 35, 42, 49, 56, 57, 50, 43, 36, 29, 22, 15, 23, 30, 37, 44, 51, 58, 59, 52, 45, 38, 31, 39, 46, 53,
    60, 61, 54, 47, 55, 62, 63])


def decode_baseline_jpeg(data):
    """Baseline (sequential, Huffman) JPEG -> H x W x 3 uint8 RGB. Enough for camera frames."""
    if data[:2] != b"\xff\xd8":
        raise ValueError("not a JPEG file")
    qt, ht, comps, restart = {}, {}, [], 0
    pos = 2
    width = height = 0
    while True:
        while data[pos] == 0xFF and data[pos + 1] == 0xFF:
            pos += 1
        if data[pos] != 0xFF:
            raise ValueError("corrupt JPEG (marker expected)")
        marker = data[pos + 1]
        length = int.from_bytes(data[pos + 2:pos + 4], "big")
        seg = data[pos + 4:pos + 2 + length]
        if marker in (0xC1, 0xC2, 0xC3, 0xC5, 0xC6, 0xC7, 0xC9, 0xCA, 0xCB, 0xCD, 0xCE, 0xCF):
            raise ValueError("only baseline JPEG is supported (this one is progressive/lossless/arithmetic)")
        if marker == 0xDB:
            p = 0
            while p < len(seg):
                prec, tid = seg[p] >> 4, seg[p] & 15
                n = 128 if prec else 64
                vals = np.frombuffer(seg[p + 1:p + 1 + n], ">u2" if prec else np.uint8).astype(np.float64)
                q = np.zeros(64)
                q[ZIGZAG] = vals
                qt[tid] = q
                p += 1 + n
        elif marker == 0xC4:
            p = 0
            while p < len(seg):
                cls, tid = seg[p] >> 4, seg[p] & 15
                counts = list(seg[p + 1:p + 17])
                syms = list(seg[p + 17:p + 17 + sum(counts)])
                # 16-bit look-up table: window -> (symbol, code length)
                lut_sym = [0] * 65536
                lut_len = [0] * 65536
                code, k = 0, 0
                for length_bits, cnt in enumerate(counts, 1):
                    for _ in range(cnt):
                        lo = code << (16 - length_bits)
                        hi = lo + (1 << (16 - length_bits))
                        lut_sym[lo:hi] = [syms[k]] * (hi - lo)
                        lut_len[lo:hi] = [length_bits] * (hi - lo)
                        code += 1
                        k += 1
                    code <<= 1
                ht[(cls, tid)] = (lut_sym, lut_len)
                p += 17 + sum(counts)
        elif marker == 0xC0:
            height = int.from_bytes(seg[1:3], "big")
            width = int.from_bytes(seg[3:5], "big")
            for i in range(seg[5]):
                cid, samp, tq = seg[6 + 3 * i], seg[7 + 3 * i], seg[8 + 3 * i]
                comps.append({"id": cid, "h": samp >> 4, "v": samp & 15, "tq": tq})
        elif marker == 0xDD:
            restart = int.from_bytes(seg[0:2], "big")
        elif marker == 0xDA:
            ns = seg[0]
            for i in range(ns):
                cid, tabs = seg[1 + 2 * i], seg[2 + 2 * i]
                for c in comps:
                    if c["id"] == cid:
                        c["td"], c["ta"] = tabs >> 4, tabs & 15
            pos = pos + 2 + length
            break
        elif marker == 0xD9:
            raise ValueError("JPEG ends before the image data")
        pos += 2 + length
    if ns != len(comps) or len(comps) not in (1, 3):
        raise ValueError("only single-scan grey or YCbCr JPEGs are supported")
    end = data.find(b"\xff\xd9", pos)
    scan = data[pos:end if end >= 0 else len(data)]
    # Split at restart markers, remove byte stuffing.
    segments, cur, i = [], bytearray(), 0
    while i < len(scan):
        byte = scan[i]
        if byte == 0xFF and i + 1 < len(scan):
            nxt = scan[i + 1]
            if nxt == 0x00:
                cur.append(0xFF)
                i += 2
                continue
            if 0xD0 <= nxt <= 0xD7:
                segments.append(bytes(cur))
                cur = bytearray()
                i += 2
                continue
        cur.append(byte)
        i += 1
    segments.append(bytes(cur))

    hmax = max(c["h"] for c in comps)
    vmax = max(c["v"] for c in comps)
    mcux = -(-width // (8 * hmax))
    mcuy = -(-height // (8 * vmax))
    for c in comps:
        c["blocks"] = np.zeros((mcuy * c["v"], mcux * c["h"], 64), np.float64)
    total = mcux * mcuy
    per_segment = restart if restart else total
    mcu = 0
    for segdata in segments:
        if mcu >= total:
            break
        bits = np.unpackbits(np.frombuffer(segdata + b"\x00\x00\x00", np.uint8)).astype(np.int64)
        nwin = len(bits) - 16
        win = np.zeros(nwin, np.int64)
        for k in range(16):
            win = (win << 1) | bits[k:k + nwin]
        win = win.tolist()
        bp = 0
        pred = [0] * len(comps)

        def receive(s):
            nonlocal bp
            v = win[bp] >> (16 - s)
            bp += s
            return v - (1 << s) + 1 if v < (1 << (s - 1)) else v

        for _ in range(min(per_segment, total - mcu)):
            my, mx = divmod(mcu, mcux)
            for ci, c in enumerate(comps):
                dsym, dlen = ht[(0, c["td"])]
                asym, alen = ht[(1, c["ta"])]
                for by in range(c["v"]):
                    for bx in range(c["h"]):
                        blk = c["blocks"][my * c["v"] + by, mx * c["h"] + bx]
                        w = win[bp]
                        s = dsym[w]
                        bp += dlen[w]
                        diff = receive(s) if s else 0
                        pred[ci] += diff
                        blk[0] = pred[ci]
                        k = 1
                        while k < 64:
                            w = win[bp]
                            rs = asym[w]
                            bp += alen[w]
                            r, s = rs >> 4, rs & 15
                            if s == 0:
                                if r == 15:
                                    k += 16
                                    continue
                                break
                            k += r
                            blk[ZIGZAG[k]] = receive(s)
                            k += 1
            mcu += 1
    # Dequantise + inverse DCT (all blocks at once), level shift, upsample, colour convert.
    u = np.arange(8)
    cu = np.where(u == 0, np.sqrt(0.5), 1.0)
    basis = 0.5 * cu[None, :] * np.cos((2 * u[:, None] + 1) * u[None, :] * np.pi / 16)  # [x, u]
    planes = []
    for c in comps:
        coef = c["blocks"] * qt[c["tq"]]
        by, bx = coef.shape[:2]
        f = coef.reshape(by, bx, 8, 8)
        pix = np.einsum("yu,abuv,xv->abyx", basis, f, basis) + 128
        plane = pix.transpose(0, 2, 1, 3).reshape(by * 8, bx * 8)
        plane = np.repeat(np.repeat(plane, vmax // c["v"], axis=0), hmax // c["h"], axis=1)
        planes.append(plane[:height, :width])
    if len(planes) == 1:
        rgb = np.stack([planes[0]] * 3, axis=-1)
    else:
        y, cb, cr = planes[0], planes[1] - 128, planes[2] - 128
        rgb = np.stack([y + 1.402 * cr, y - 0.344136 * cb - 0.714136 * cr, y + 1.772 * cb], axis=-1)
    return np.clip(np.round(rgb), 0, 255).astype(np.uint8)


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos)
            continue
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        fields.append(data[start:pos])
    if fields[0] not in (b"P6", b"P5") or int(fields[3]) > 255:
        raise ValueError(f"{path}: only 8-bit binary PPM (P6) / PGM (P5) is supported")
    w, h = int(fields[1]), int(fields[2])
    ch = 3 if fields[0] == b"P6" else 1
    img = np.frombuffer(data[pos + 1:pos + 1 + w * h * ch], np.uint8).reshape(h, w, ch)
    return np.repeat(img, 3, axis=2) if ch == 1 else img


def load_image(path):
    """-> (H x W x 3 uint8 RGB, None) or (None, NCHW float32 blob) for a ready network input."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".npy":
        a = np.load(path)
        if a.ndim == 4:
            return None, a.astype(np.float32)
        if a.ndim == 3 and a.shape[2] == 3:
            return a.astype(np.uint8), None
        raise ValueError(f"{path}: expected H x W x 3 uint8 or an NCHW blob, got {a.shape}")
    if ext in (".ppm", ".pgm", ".pnm"):
        return read_ppm(path), None
    if ext in (".jpg", ".jpeg"):
        try:
            from PIL import Image  # optional
            return np.asarray(Image.open(path).convert("RGB")), None
        except ImportError:
            with open(path, "rb") as f:
                return decode_baseline_jpeg(f.read()), None
    raise ValueError(f"{path}: unsupported image type (jpg, ppm, pgm, npy)")


def resize_bilinear_half_pixel(img, oh, ow):
    """H x W x C -> oh x ow x C float32, bilinear with half-pixel centres (cv::resize INTER_LINEAR)."""
    h, w = img.shape[:2]

    def axis(o, i):
        src = np.clip((np.arange(o) + 0.5) * (i / o) - 0.5, 0, i - 1)
        lo = np.floor(src).astype(int)
        hi = np.minimum(lo + 1, i - 1)
        return lo, hi, src - lo

    y0, y1, fy = axis(oh, h)
    x0, x1, fx = axis(ow, w)
    f = img.astype(np.float64)
    fx = fx[None, :, None]
    top = f[y0][:, x0] * (1 - fx) + f[y0][:, x1] * fx
    bottom = f[y1][:, x0] * (1 - fx) + f[y1][:, x1] * fx
    return (top * (1 - fy[:, None, None]) + bottom * fy[:, None, None]).astype(np.float32)


# ----------------------------------------------------------------------------------------------
# Detections (for a human to judge)
# ----------------------------------------------------------------------------------------------

def detections(heat, wh, classes, threshold, top, stride, box_scale, in_w, in_h, img_w, img_h):
    """heat [C, H, W], wh [4, H, W] (NCHW without batch) -> [(class, score, x0, y0, x1, y1)] in image pixels."""
    c, h, w = heat.shape
    pad = np.pad(heat, ((0, 0), (1, 1), (1, 1)), constant_values=-np.inf)
    peak = np.ones_like(heat, bool)
    for dy in range(3):
        for dx in range(3):
            if dy != 1 or dx != 1:
                peak &= heat >= pad[:, dy:dy + h, dx:dx + w]
    ks, ys, xs = np.nonzero(peak & (heat >= threshold))
    order = np.argsort(-heat[ks, ys, xs], kind="stable")[:top]
    sx, sy = img_w / in_w, img_h / in_h
    out = []
    for i in order:
        k, y, x = ks[i], ys[i], xs[i]
        l, t, r, b = (wh[:, y, x] * box_scale).tolist()
        cx, cy = stride * x, stride * y
        name = classes[k] if classes and k < len(classes) else f"class {k}"
        clip = lambda v, hi: min(max(v, 0.0), hi)  # noqa: E731
        out.append((name, float(heat[k, y, x]), clip((cx - l) * sx, img_w), clip((cy - t) * sy, img_h),
                    clip((cx + r) * sx, img_w), clip((cy + b) * sy, img_h)))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model_json", help="the original TF.js graph model")
    ap.add_argument("onnx_file", help="the converted ONNX file")
    ap.add_argument("--description", help="model description (pndt-segmentation-model/1 JSON): classes, detector settings")
    ap.add_argument("--tf-input", default="tower_0/images")
    ap.add_argument("--onnx-input", default="rgb")
    ap.add_argument("--output", action="append", default=[], help="ONNX_NAME=TF_NODE (default: CenterNet's two)")
    ap.add_argument("--image", action="append", default=[], help="test image(s): jpg, ppm, npy; default: pseudo-random")
    ap.add_argument("--tol", type=float, default=1e-3, help="max abs difference allowed on the heatmap")
    ap.add_argument("--box-tol", type=float, default=0.05, help="max abs difference allowed on box_size (512-input pixels)")
    ap.add_argument("--top", type=int, default=10, help="detections to print per image")
    ap.add_argument("--threshold", type=float, help="score threshold of the printed detections "
                    "(default: the description's detector.score_threshold, else 0.3)")
    ap.add_argument("--save-reference", help="write the first image's input and TF.js outputs to this .npz")
    ap.add_argument("--save-reference-dir", help="... and as input.npy / <output>.npy in this folder")
    a = ap.parse_args()
    outputs = [o.split("=", 1) for o in (a.output or ["heatmap=tower_0/keypoints", "box_size=tower_0/wh"])]

    try:
        t0 = time.time()
        tfm = TfjsModel(a.model_json)
        dims = [int(d["size"]) for d in tfm.nodes[a.tf_input]["attr"]["shape"]["shape"]["dim"]]
        in_h, in_w = dims[1], dims[2]
        desc = {}
        if a.description:
            with open(a.description) as f:
                desc = json.load(f)
        det = desc.get("detector", {})
        classes = desc.get("classes", [])
        images = a.image or [None]
        inputs = []
        for path in images:
            if path is None:
                rng = np.random.RandomState(20261125)
                img, blob, label = rng.randint(0, 256, (480, 640, 3)).astype(np.uint8), None, "pseudo-random 640x480"
            else:
                img, blob = load_image(path)
                label = path
            if blob is None:
                blob = resize_bilinear_half_pixel(img, in_h, in_w).transpose(2, 0, 1)[None].copy()
                size = (img.shape[1], img.shape[0])
            else:
                size = (640, 480)  # a ready blob: boxes reported for a 640x480 frame
            if blob.shape != (1, 3, in_h, in_w):
                raise ValueError(f"{label}: input blob has shape {blob.shape}, the network wants [1, 3, {in_h}, {in_w}]")
            inputs.append((label, blob, size))
    except (OSError, ValueError, KeyError) as e:
        print(f"check_conversion: error: {e}", file=sys.stderr)
        return 2
    print(f"check_conversion: read {a.model_json} ({len(tfm.nodes)} nodes, {len(tfm.weights)} weights) "
          f"and {len(inputs)} image(s) in {time.time() - t0:.1f} s")

    failed = False
    for idx, (label, blob, (img_w, img_h)) in enumerate(inputs):
        t1 = time.time()
        ref = tfm.run({a.tf_input: blob.transpose(0, 2, 3, 1)}, [t for _, t in outputs])
        ref = {name: np.ascontiguousarray(v.transpose(0, 3, 1, 2)) for (name, _), v in zip(outputs, ref)}
        t2 = time.time()
        got = run_onnx(a.onnx_file, {a.onnx_input: blob})
        t3 = time.time()
        print(f"\n{label}: TF.js graph (NumPy, NHWC) {t2 - t1:.1f} s, ONNX (NumPy, NCHW) {t3 - t2:.1f} s")
        for name, r in ref.items():
            g = got.get(name)
            if g is None or g.shape != r.shape:
                print(f"  {name}: ONNX output missing or shaped {None if g is None else g.shape}, expected {r.shape}")
                failed = True
                continue
            diff = float(np.max(np.abs(g.astype(np.float64) - r)))
            tol = a.tol if name == "heatmap" or name == outputs[0][0] else a.box_tol
            ok = diff <= tol
            failed |= not ok
            print(f"  {name} {list(r.shape)}: max abs diff {diff:.3g} (tolerance {tol:g}) "
                  f"range [{float(r.min()):.4g}, {float(r.max()):.4g}] {'ok' if ok else 'FAILED'}")
        if "heatmap" in ref and "box_size" in ref:
            thr = a.threshold if a.threshold is not None else float(det.get("score_threshold", 0.3))
            dets = detections(ref["heatmap"][0], ref["box_size"][0], classes, thr,
                              a.top, int(det.get("stride", 4)), float(det.get("box_scale", 1.0)), in_w, in_h, img_w, img_h)
            print(f"  detections (score >= {thr:g}, boxes in {img_w}x{img_h} image pixels):"
                  + ("" if dets else " none"))
            for name, score, x0, y0, x1, y1 in dets:
                print(f"    {name:<14} {score:.3f}  [{x0:6.1f}, {y0:6.1f}, {x1:6.1f}, {y1:6.1f}]")
        if idx == 0 and (a.save_reference or a.save_reference_dir):
            if a.save_reference:
                tmp = a.save_reference + ".tmp.npz"
                np.savez(tmp, input=blob.astype(np.float32), **{k: v.astype(np.float32) for k, v in ref.items()})
                os.replace(tmp, a.save_reference)
                print(f"  wrote {a.save_reference} (input, {', '.join(ref)}: NCHW float32, TF.js graph outputs)")
            if a.save_reference_dir:
                os.makedirs(a.save_reference_dir, exist_ok=True)
                for k, v in [("input", blob)] + list(ref.items()):
                    p = os.path.join(a.save_reference_dir, k + ".npy")
                    np.save(p + ".tmp.npy", v.astype(np.float32))
                    os.replace(p + ".tmp.npy", p)
                print(f"  wrote {a.save_reference_dir}/{{input,{','.join(ref)}}}.npy")
    print("\ncheck_conversion: " + ("FAILED: the ONNX file disagrees with the original graph" if failed
                                    else "the ONNX file agrees with the original TF.js graph"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
