#!/usr/bin/env python3
"""Validates brdfbake's EXT_lights_image_based output against tests/engines/EXT_lights_image_based.schema.json
(written from the extension's specification text) with python3-jsonschema, then checks what a schema
cannot: every index points at an image, every image file exists, is a PNG with an alpha channel
(RGBD, as the extension reads 4-channel PNGs) of its level's size (specularImageSize >> level), the
size is a power of two, and the scene references an existing light.

The document comes from test_host's GltfIbl test, run with BRDFBAKE_GLTF_OUT set to a fresh folder.
Exit code 77 (ctest's skip) when jsonschema is not installed."""
import argparse
import json
import os
import struct
import subprocess
import sys
import tempfile


def png_header(path):
    with open(path, "rb") as f:
        head = f.read(33)
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        raise ValueError(f"{path}: not a PNG")
    width, height, depth, colour = struct.unpack(">IIBB", head[16:26])
    return width, height, depth, colour


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--schema", required=True)
    parser.add_argument("--write-with", required=True, help="test_host, which writes the document")
    args = parser.parse_args()
    try:
        import jsonschema
    except ImportError:
        print("SKIP: python3-jsonschema is not installed (apt-get install python3-jsonschema)")
        return 77
    with tempfile.TemporaryDirectory() as out:
        env = dict(os.environ, BRDFBAKE_GLTF_OUT=out)
        run = subprocess.run([args.write_with, "--gtest_filter=GltfIbl.DocumentImagesAndCoefficients"],
                             env=env, capture_output=True, text=True)
        if run.returncode != 0:
            print(run.stdout[-3000:], run.stderr[-3000:])
            print("FAIL: the test that writes the document failed")
            return 1
        path = os.path.join(out, "env.gltf")
        with open(path) as f:
            doc = json.load(f)
        with open(args.schema) as f:
            schema = json.load(f)
        errors = sorted(jsonschema.Draft7Validator(schema).iter_errors(doc), key=lambda e: list(e.path))
        for e in errors:
            print(f"schema: {'/'.join(map(str, e.path))}: {e.message}")
        problems = len(errors)
        lights = doc["extensions"]["EXT_lights_image_based"]["lights"]
        for scene in doc["scenes"]:
            ref = scene.get("extensions", {}).get("EXT_lights_image_based")
            if ref is not None and not 0 <= ref["light"] < len(lights):
                print(f"scene references light {ref['light']} of {len(lights)}")
                problems += 1
        for light in lights:
            size = light["specularImageSize"]
            if size != int(size) or int(size) & (int(size) - 1):
                print(f"specularImageSize {size} is not a power of two")
                problems += 1
            for level, faces in enumerate(light["specularImages"]):
                for index in faces:
                    if not 0 <= index < len(doc["images"]):
                        print(f"level {level}: image index {index} out of range")
                        problems += 1
                        continue
                    image = os.path.join(out, doc["images"][index]["uri"])
                    width, height, depth, colour = png_header(image)
                    if (width, height) != (int(size) >> level, int(size) >> level) or depth != 8 or colour != 6:
                        print(f"{image}: {width}x{height} depth {depth} colour type {colour}, expected "
                              f"{int(size) >> level}^2 8-bit RGBA (RGBD)")
                        problems += 1
        checked = sum(len(faces) for light in lights for faces in light["specularImages"])
        print(f"{path}: {len(errors)} schema errors, {problems - len(errors)} reference errors, {checked} images checked")
        print(f"{1 if problems == 0 else 0} passed, {1 if problems else 0} failed")
        return 0 if problems == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
