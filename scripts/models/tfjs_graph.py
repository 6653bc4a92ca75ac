"""Reading a TF.js graph model (model.json + weight shards) into plain Python: nodes by name,
constants as NumPy arrays (float16 weights widened to float32). Shared by the ONNX converter and
the NumPy reference that checks it."""
import base64
import json
import os

import numpy as np

DTYPES = {"float32": np.float32, "int32": np.int32, "float16": np.float16, "uint8": np.uint8, "bool": np.bool_}


class GraphModel:
    def __init__(self, model_json):
        with open(model_json) as f:
            m = json.load(f)
        self.nodes = {n["name"]: n for n in m["modelTopology"]["node"]}
        self.order = [n["name"] for n in m["modelTopology"]["node"]]
        self.consts = {}
        folder = os.path.dirname(os.path.abspath(model_json))
        for group in m["weightsManifest"]:
            data = b"".join(open(os.path.join(folder, p), "rb").read() for p in group["paths"])
            offset = 0
            for w in group["weights"]:
                stored = w.get("quantization", {}).get("dtype", w["dtype"])
                if stored not in DTYPES:
                    raise ValueError(f"{model_json}: weight {w['name']} has unsupported dtype {stored}")
                count = int(np.prod(w["shape"])) if w["shape"] else 1
                nbytes = count * np.dtype(DTYPES[stored]).itemsize
                if offset + nbytes > len(data):
                    raise ValueError(f"{model_json}: weight shards end inside {w['name']} (truncated .bin?)")
                arr = np.frombuffer(data, DTYPES[stored], count, offset).reshape(w["shape"])
                offset += nbytes
                self.consts[w["name"]] = arr.astype(DTYPES[w["dtype"]])
            if offset != len(data):
                raise ValueError(f"{model_json}: {len(data) - offset} bytes left over in the weight shards")

    def attr(self, name, key, default=None):
        a = self.nodes[name].get("attr", {}).get(key)
        if a is None:
            return default
        if "s" in a:
            return base64.b64decode(a["s"]).decode()
        if "list" in a:
            lst = a["list"]
            if "i" in lst:
                return [int(v) for v in lst["i"]]
            if "s" in lst:
                return [base64.b64decode(v).decode() for v in lst["s"]]
            return []
        if "b" in a:
            return bool(a["b"])
        if "i" in a:
            return int(a["i"])
        if "f" in a:
            return float(a["f"])
        return a

    def inputs(self, name):
        return [i.split(":")[0] if not i.endswith(":0") else i[:-2] for i in self.nodes[name].get("input", [])]

    def const(self, name):
        if name not in self.consts:
            raise ValueError(f"expected a constant for {name}")
        return self.consts[name]

    def is_const(self, name):
        return name in self.consts

    def upstream(self, outputs):
        """Names of the non-constant nodes the outputs depend on, in graph order."""
        needed, stack = set(), list(outputs)
        while stack:
            n = stack.pop()
            if n in needed or n in self.consts:
                continue
            needed.add(n)
            stack.extend(self.inputs(n))
        return [n for n in self.order if n in needed]


def same_pads(in_size, k, s, d=1):
    """TensorFlow SAME padding (before, after) of one axis: the extra pixel goes after."""
    out = -(-in_size // s)
    total = max((out - 1) * s + (k - 1) * d + 1 - in_size, 0)
    return total // 2, total - total // 2
