#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""A Fig. 20 analogue (paper section VI.D): vectorize a photo of a cup, then edit the
vectorized image: warp the longest feature pair by moving its deBoor points, recolour a
region, make the blurred edges of part of the picture sharp. Writes before/after PNGs.

usage: scripts/edit_fig20.py [--sdvi build/cli/sdvi] [--image ../shared/data/photos/coffee.png]
                             [--out out/fig20]
Writes into OUT: coffee.sdvi, features.json, edits.json, edited.sdvi, before.png,
after.png, overlay.png and after_overlay.png (feature ids over the renders, 2x) and prints
what it picked.
The region and the warp are placed relative to the picked features and the image size,
so any photo with curved features works; the defaults are set for coffee.png.
"""
import argparse
import json
import math
import os
import subprocess
import sys


def run(*args):
    print("+", " ".join(args), flush=True)
    subprocess.run(args, check=True)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sdvi", default=os.path.join(root, "build", "cli", "sdvi"))
    p.add_argument("--image", default=os.path.join(root, "..", "shared", "data", "photos", "coffee.png"))
    p.add_argument("--out", default=os.path.join(root, "out", "fig20"))
    p.add_argument("--warp", type=float, default=10.0, help="how far the middle of the warped pair moves, px")
    p.add_argument("--warp-pair", type=int, default=-1, help="the pair to warp (default: the longest)")
    p.add_argument("--hue", type=float, default=150.0, help="hue shift of the recoloured region, degrees")
    p.add_argument("--reuse", action="store_true", help="keep OUT/coffee.sdvi when it exists")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    sdvi_file = os.path.join(a.out, "coffee.sdvi")
    if not (a.reuse and os.path.exists(sdvi_file)):
        run(a.sdvi, "vectorize", a.image, "-o", sdvi_file, "--quiet")

    info = subprocess.run([a.sdvi, "info", sdvi_file, "--features", "--json"], check=True,
                          capture_output=True, text=True).stdout
    with open(os.path.join(a.out, "features.json"), "w") as f:
        f.write(info)
    info = json.loads(info)
    width, height = info["width"], info["height"]
    features = info["features"]
    pairs = [f for f in features if f["kind"] == "pair"]
    polylines = {f["id"]: f for f in features if f["kind"] != "pair"}
    if not pairs:
        sys.exit("no feature pair to edit")

    # 1. Warp: a pair (--warp-pair, default the longest) bends sideways: deBoor point k of
    #    both sides moves by warp * sin^2(pi k / (n - 1)) along the pair's mean normal (from
    #    its first side to its second), so the ends stay and the middle moves most; the rest
    #    of the mesh follows by the rigid moving-least-squares deformation (boundary pinned).
    warp = next((f for f in pairs if f["id"] == a.warp_pair), None) if a.warp_pair >= 0 else \
        max(pairs, key=lambda f: f["length"])
    if warp is None:
        sys.exit(f"no pair {a.warp_pair}")
    first = polylines[warp["first"]]["deboor_points"]
    second = polylines[warp["second"]]["deboor_points"]
    n = len(first)
    nx = sum(q[1] - p[1] for p, q in zip(first, second))
    ny = sum(q[2] - p[2] for p, q in zip(first, second))
    norm = math.hypot(nx, ny) or 1.0
    nx, ny = nx / norm, ny / norm
    handles = []
    for k in range(n):
        amount = a.warp * math.sin(math.pi * k / (n - 1)) ** 2 if n > 1 else 0.0
        for v, x, y in (first[k], second[k]):
            handles.append({"vertex": v, "to": [x + amount * nx, y + amount * ny]})

    # 2. Recolour: a hue shift of the vertices strictly inside the inner side of the warped
    #    pair (the side whose deBoor points span the smaller box): in coffee.png the rim of
    #    the cup, so the coffee changes colour. Runs before the warp, on the positions above.
    def box_area(points):
        xs, ys = [p[1] for p in points], [p[2] for p in points]
        return (max(xs) - min(xs)) * (max(ys) - min(ys))
    inner = min((first, second), key=box_area)
    region = [[x, y] for _, x, y in inner]

    ops = [{"op": "hsl_shift", "select": {"region": region}, "hue": a.hue},
           {"op": "deform", "handles": handles}]
    script = os.path.join(a.out, "edits.json")
    warped = os.path.join(a.out, "warped.sdvi")
    with open(script, "w") as f:
        json.dump({"sdvi_edit": 1, "ops": ops}, f, indent=1)
    run(a.sdvi, "edit", sdvi_file, "-o", warped, "--script", script, "--quiet")

    # 3. Sharpen: the blurred pairs (sharpness < 0.5) in the left half become sharp. A pair
    #    whose narrower strip folds triangles (at a tight curl of its ends) is re-triangulated
    #    by edge flips (--repair); one that still folds is refused by sdvi edit's validity
    #    rule: each is tried alone and the refused ones are left out.
    soft, refused = [], []
    for f in pairs:
        if f["sharpness"] < 0.5 and f["bbox"][2] < width / 2:
            trial = subprocess.run([a.sdvi, "edit", warped, "-o", os.path.join(a.out, "trial.sdvi"), "--quiet",
                                    "--repair", "--sharpness", f"{f['id']}=1"], capture_output=True, text=True)
            (soft if trial.returncode == 0 else refused).append(f)
            if trial.returncode != 0:
                print(f"P{f['id']}: {trial.stderr.strip()}")
    ops += [{"op": "set_sharpness", "pair": f["id"], "sharpness": 1} for f in soft]
    with open(script, "w") as f:
        json.dump({"sdvi_edit": 1, "ops": ops}, f, indent=1)
    print(f"warp: pair P{warp['id']} (length {warp['length']:.0f} px) by up to {a.warp} px, {len(handles)} handles; "
          f"recolour: inside the {len(region)}-point inner side of P{warp['id']}, hue {a.hue:+.0f} deg; "
          f"sharpen: {len(soft)} blurred pairs {['P%d' % f['id'] for f in soft]} "
          f"({len(refused)} refused: {['P%d' % f['id'] for f in refused]})")

    edited = os.path.join(a.out, "edited.sdvi")
    run(a.sdvi, "edit", sdvi_file, "-o", edited, "--script", script, "--repair")
    run(a.sdvi, "render", sdvi_file, "-o", os.path.join(a.out, "before.png"))
    run(a.sdvi, "render", edited, "-o", os.path.join(a.out, "after.png"))
    run(a.sdvi, "render", sdvi_file, "-o", os.path.join(a.out, "overlay.png"), "--overlay", "features", "--scale", "2")
    run(a.sdvi, "render", edited, "-o", os.path.join(a.out, "after_overlay.png"), "--overlay", "features", "--scale", "2")
    print("wrote", ", ".join(os.path.join(a.out, n) for n in ("before.png", "after.png", "overlay.png", "after_overlay.png")))


if __name__ == "__main__":
    main()
