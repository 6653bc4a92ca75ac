#!/usr/bin/env python3
"""Writes the text/image/npz seed corpora of the fuzz targets (stdlib only), from the
fixtures the reader tests use. The map archive and rawlog seeds come from the
fuzz_make_seeds program (make_seeds.cpp). Usage: make_seeds.py CORPUS_DIR"""
import io, os, struct, sys, zipfile, zlib

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "corpus")
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def put(target, name, data):
    d = os.path.join(out, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def npy(shape, values):
    header = "{'descr': '<f4', 'fortran_order': False, 'shape': (%s), }" % (
        ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else ""))
    header += " " * ((64 - (10 + len(header) + 1) % 64) % 64) + "\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode() + struct.pack(
        "<%df" % len(values), *values)


# npy / npz: EMSANet "mapping" outputs, id + score, shapes (1,H,W), (H,W), (K,H,W)
sem = npy((1, 2, 3), [1.9, 1.9, 5.5, 0.0, 3.25, 40.999])
inst = npy((2, 3), [0, 7.8, 7.8, 0, 12.5, 0])
topk = npy((2, 2, 2), [1.9, 2.8, 3.7, 4.6, 5.5, 6.4, 7.3, 8.2])
put("npy", "semantic.npy", sem)
put("npy", "instance.npy", inst)
put("npy", "topk.npy", topk)
for name, arr, comp in (("stored.npz", sem, zipfile.ZIP_STORED), ("deflated.npz", inst, zipfile.ZIP_DEFLATED),
                        ("topk.npz", topk, zipfile.ZIP_DEFLATED)):
    b = io.BytesIO()
    with zipfile.ZipFile(b, "w", comp) as z:
        with z.open("arr_0.npy", "w", force_zip64=True) as m:  # as np.savez_compressed writes
            m.write(arr)
    put("npz", name, b.getvalue())


def png(w, h, bit_depth, colour_type, rows):
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + r for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bit_depth, colour_type, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


depth16 = png(4, 3, 16, 0, [struct.pack(">4H", 0, 1000, 2000, 65535)] * 3)
label8 = png(4, 3, 8, 0, [bytes([0, 1, 5, 40])] * 3)
label16 = png(4, 3, 16, 0, [struct.pack(">4H", 0, 7, 1000, 40000)] * 3)
nicr_rgb = png(2, 2, 8, 2, [bytes([3, 0, 7, 5, 1, 2])] * 2)
rgba = png(2, 2, 8, 6, [bytes([10, 20, 30, 255, 40, 50, 60, 128])] * 2)
for sel, name, data in ((0, "depth16.png", depth16), (1, "depth16_tum.png", depth16), (2, "label8.png", label8),
                        (2, "label16.png", label16), (2, "label_nicr.png", nicr_rgb), (3, "rgb.png", nicr_rgb),
                        (3, "rgba.png", rgba), (0, "depth.pgm", b"P5 2 2 65535\n" + bytes(8))):
    put("image", name, bytes([sel]) + data)

# JSON readers: selector byte, then the file
open3d = '{"width":640,"height":480,"intrinsic_matrix":[525,0,0,0,525,0,319.5,239.5,1]}'
nicr_k = '{"fx": 0.8203125, "fy": 1.09375, "cx": 0.49921875, "cy": 0.49895833, "a": 0.001, "b": -1}'
nicr_t = ('{"x": 1.5, "y": -0.25, "z": 2.0, "quat_x": 0.0, "quat_y": 0.0, "quat_z": 0.38268343, '
          '"quat_w": 0.92387953}')
nicr_nan = '{"x": NaN, "y": 0, "z": Infinity, "quat_x": 0, "quat_y": 0, "quat_z": 0, "quat_w": 1}'
put("json", "open3d.json", b"\x00" + open3d.encode())
put("json", "nicr_intrinsics.json", b"\x01" + nicr_k.encode())
put("json", "nicr_extrinsics.json", b"\x02" + nicr_t.encode())
put("json", "nicr_extrinsics_nan.json", b"\x02" + nicr_nan.encode())
with open(os.path.join(root, "models", "centernet_coco.json"), "rb") as f:
    put("json", "model_detector.json", b"\x03" + f.read())

# pose text formats: selector (index into tum, rtabmap0/1/2/4/10/11, kitti, redwood)
q = "0 0 0.38268343 0.92387953"
m34 = "1 0 0 0.5 0 1 0 -0.25 0 0 1 2"
poses = {
    0: "# timestamp tx ty tz qx qy qz qw\n1305031102.175304 1.3405 0.6266 1.6575 " + q + "\n1305031102.2 1.3 0.6 1.6 " + q + "\n",
    1: m34 + "\n" + m34 + "\nnan nan nan nan 0 1 0 0 0 0 1 0\n",
    2: "#timestamp x y z qx qy qz qw\n0.1 1 2 3 " + q + "\n0.2 1 2 3 " + q + "\n",
    3: m34 + "\n",
    4: "VERTEX_SE3:QUAT 1 1 2 3 " + q + "\nVERTEX_SE2 2 1 2 0.5\nEDGE_SE3:QUAT 1 2 0 0 0 0 0 0 1\nFIX 1\n",
    5: "0.1 1 2 3 " + q + "\n",
    6: "0.1 1 2 3 " + q + " 17\n0.2 1 2 3 " + q + " 18\n",
    7: m34 + "\n" + m34 + "\n",
    8: "0 0 2\n1 0 0 0.5\n0 1 0 0\n0 0 1 0\n0 0 0 1\n1 1 2\n1 0 0 0.6\n0 1 0 0\n0 0 1 0\n0 0 0 1\n",
}
for sel, text in poses.items():
    put("pose_text", "format_%d.txt" % sel, bytes([sel]) + text.encode())
put("pose_text", "tum_nan_strict.txt", bytes([0x80]) + poses[0].replace("1.3405", "nan").encode())

# ini layering: base \0 layer \0 overrides (one per line)
with open(os.path.join(root, "config", "panoptic_ndt.ini"), "rb") as f:
    base = f.read()
put("ini", "layers.ini", base[:1500] + b"\0[PanopticNDTMap]\nvoxel_size = 0.05\n\0PanopticNDTMap.voxel_size=0.1\nmapping.x=1\n")
put("ini", "overrides.ini", b"[a]\nk=1\n\0[map_x]\nk = 2 ; c\n\0a.k=3\nbad\n")
