"""A NumPy interpreter of the TF.js graph ops a CenterNet / MobileNet model uses, in the graph's
own NHWC layout with its original weights: the reference the converted ONNX file is checked
against (and the source of the tensor shapes the converter needs for SAME padding)."""
import numpy as np

from tfjs_graph import same_pads


def _pad(x, kh, kw, sh, sw, dh, dw, padding):
    if padding == "VALID":
        return x
    ph = same_pads(x.shape[1], kh, sh, dh)
    pw = same_pads(x.shape[2], kw, sw, dw)
    return np.pad(x, ((0, 0), ph, pw, (0, 0)))


def conv2d(x, w, strides, padding, dilations, depthwise):
    kh, kw = w.shape[0], w.shape[1]
    sh, sw = strides[1], strides[2]
    dh, dw = (dilations[1], dilations[2]) if dilations else (1, 1)
    xp = _pad(x, kh, kw, sh, sw, dh, dw, padding)
    oh = (xp.shape[1] - (kh - 1) * dh - 1) // sh + 1
    ow = (xp.shape[2] - (kw - 1) * dw - 1) // sw + 1
    out = None
    for i in range(kh):
        for j in range(kw):
            patch = xp[:, i * dh: i * dh + (oh - 1) * sh + 1: sh, j * dw: j * dw + (ow - 1) * sw + 1: sw, :]
            term = patch * w[i, j, :, 0] if depthwise else patch @ w[i, j]
            out = term if out is None else out + term
    return out.astype(np.float32)


def resize_bilinear(x, size, align_corners, half_pixel):
    if align_corners or half_pixel:
        raise ValueError("ResizeBilinear: only align_corners = half_pixel_centers = false is implemented")
    h, w = x.shape[1], x.shape[2]
    oh, ow = int(size[0]), int(size[1])

    def axis(o, i):
        src = np.arange(o) * (i / o)
        i0 = np.floor(src).astype(int)
        i1 = np.minimum(i0 + 1, i - 1)
        return i0, i1, (src - i0).astype(np.float32)

    y0, y1, fy = axis(oh, h)
    x0, x1, fx = axis(ow, w)
    top = x[:, y0][:, :, x0] * (1 - fx)[None, None, :, None] + x[:, y0][:, :, x1] * fx[None, None, :, None]
    bot = x[:, y1][:, :, x0] * (1 - fx)[None, None, :, None] + x[:, y1][:, :, x1] * fx[None, None, :, None]
    return (top * (1 - fy)[None, :, None, None] + bot * fy[None, :, None, None]).astype(np.float32)


def run(g, outputs, feeds):
    """Evaluates `outputs` of GraphModel g; feeds: {placeholder name: NHWC array}."""
    vals = dict(feeds)

    def v(name):
        return vals[name] if name in vals else g.const(name)

    for name in g.upstream(outputs):
        if name in vals:
            continue
        op = g.nodes[name]["op"]
        ins = g.inputs(name)
        if op == "Placeholder":
            raise ValueError(f"no input fed for {name}")
        if op in ("_FusedConv2D", "FusedDepthwiseConv2dNative", "Conv2D", "DepthwiseConv2dNative"):
            depthwise = "Depthwise" in op
            y = conv2d(v(ins[0]), v(ins[1]), g.attr(name, "strides"), g.attr(name, "padding"),
                       g.attr(name, "dilations"), depthwise)
            fused = g.attr(name, "fused_ops", []) if op.startswith(("_", "Fused")) else []
            for f in fused:
                if f == "BiasAdd":
                    y = y + v(ins[2])
                elif f == "Relu":
                    y = np.maximum(y, 0)
                elif f == "Relu6":
                    y = np.clip(y, 0, 6)
                else:
                    raise ValueError(f"{name}: unsupported fused op {f}")
            vals[name] = y.astype(np.float32)
        elif op == "Add" or op == "AddV2":
            vals[name] = (v(ins[0]) + v(ins[1])).astype(np.float32)
        elif op == "Sub":
            vals[name] = (v(ins[0]) - v(ins[1])).astype(np.float32)
        elif op == "Mul":
            vals[name] = (v(ins[0]) * v(ins[1])).astype(np.float32)
        elif op == "Relu":
            vals[name] = np.maximum(v(ins[0]), 0)
        elif op == "Relu6":
            vals[name] = np.clip(v(ins[0]), 0, 6)
        elif op == "Sigmoid":
            vals[name] = (1 / (1 + np.exp(-v(ins[0])))).astype(np.float32)
        elif op == "Identity":
            vals[name] = v(ins[0])
        elif op == "Mean":
            axes = tuple(int(a) for a in np.atleast_1d(v(ins[1])))
            vals[name] = v(ins[0]).mean(axis=axes, keepdims=bool(g.attr(name, "keep_dims", False))).astype(np.float32)
        elif op == "ConcatV2":
            axis = int(v(ins[-1]))
            vals[name] = np.concatenate([v(i) for i in ins[:-1]], axis=axis)
        elif op == "ResizeBilinear":
            vals[name] = resize_bilinear(v(ins[0]), v(ins[1]), g.attr(name, "align_corners", False),
                                         g.attr(name, "half_pixel_centers", False))
        else:
            raise ValueError(f"{name}: op {op} is not supported by this reference")
    return [vals[o] for o in outputs]
