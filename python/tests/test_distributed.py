# SPDX-License-Identifier: GPL-3.0-or-later
"""The binding and the Dask driver on a LocalCluster with 2 worker processes.

usage: test_distributed.py SDVI_EXECUTABLE   (PYTHONPATH holds the built sdvi package)

Inputs are generated here (`sdvi sample` at three sizes, one file of garbage); the checks:
outputs byte-identical to `sdvi vectorize` and `sdvi render`, the failing input reported
by name while the others finish, the JSON-lines report, a second run skipping every
finished output, and the array entry points giving the same image as the file ones.
"""

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

import sdvi
from sdvi.distributed import map_files


def check(condition, what):
    if not condition:
        raise AssertionError(what)


def main():
    cli = sys.argv[1]
    from distributed import Client, LocalCluster

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        inputs = tmp / "in"
        inputs.mkdir()
        for name, (w, h) in {"a": (96, 72), "b": (80, 64), "c": (64, 64)}.items():
            subprocess.run([cli, "sample", "-o", str(inputs / f"{name}.png"), "--width", str(w),
                            "--height", str(h)], check=True)
        (inputs / "broken.png").write_bytes(b"not a png at all")

        # What the command writes, for the byte comparison.
        expected = {}
        for name in "abc":
            out = tmp / f"cli_{name}.sdvi"
            subprocess.run([cli, "vectorize", str(inputs / f"{name}.png"), "-o", str(out), "--quiet"], check=True)
            expected[name] = out.read_bytes()

        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
        try:
            report = tmp / "report.jsonl"
            outputs = tmp / "out"
            records = map_files(client, str(inputs), str(outputs), report=str(report))
            check([Path(r["input"]).name for r in records] == ["a.png", "b.png", "broken.png", "c.png"],
                  f"records in input order: {records}")
            status = {Path(r["input"]).stem: r["status"] for r in records}
            check(status == {"a": "ok", "b": "ok", "broken": "failed", "c": "ok"}, f"statuses: {status}")
            broken = next(r for r in records if r["status"] == "failed")
            check("broken.png" in broken["error"], f"error names the file: {broken['error']}")
            check(not (outputs / "broken.sdvi").exists(), "no output for the failed input")
            check(len({r["pid"] for r in records}) >= 1, "records carry the worker process")
            for name in "abc":
                check((outputs / f"{name}.sdvi").read_bytes() == expected[name],
                      f"{name}.sdvi differs from `sdvi vectorize`")
            lines = [json.loads(line) for line in report.read_text().splitlines()]
            check(len(lines) == 4 and {Path(l["input"]).stem for l in lines} == {"a", "b", "broken", "c"},
                  "one report line per input")
            check(all(l["report"]["triangles"] > 0 for l in lines if l["status"] == "ok"),
                  "vectorize records carry the report")

            # Resume: finished outputs are skipped, the failed input is tried again.
            again = map_files(client, str(inputs), str(outputs), report=str(report))
            status = {Path(r["input"]).stem: r["status"] for r in again}
            check(status == {"a": "skipped", "b": "skipped", "broken": "failed", "c": "skipped"},
                  f"second run statuses: {status}")
            check(len(report.read_text().splitlines()) == 8, "report appended")

            # Render over the cluster: the same PNG as `sdvi render`.
            renders = map_files(client, str(outputs / "*.sdvi"), str(tmp / "png"), command="render",
                                options={"scale": 2.0})
            check([r["status"] for r in renders] == ["ok"] * 3, f"render statuses: {renders}")
            subprocess.run([cli, "render", str(outputs / "a.sdvi"), "-o", str(tmp / "cli_a.png"), "--scale", "2",
                            "--quiet"], check=True)
            check((tmp / "png" / "a.png").read_bytes() == (tmp / "cli_a.png").read_bytes(),
                  "a.png differs from `sdvi render`")
        finally:
            client.close()
            cluster.close()

        # Arrays: an 8-bit array is the PNG's raster, so the image is the same.
        from_file = sdvi.load(str(outputs / "a.sdvi"))
        pixels = sdvi.render(from_file)
        check(pixels.shape == (72, 96, 4) and pixels.dtype == np.float32, f"render shape {pixels.shape}")
        rgb = np.clip(np.rint(pixels[:, :, :3]), 0, 255).astype(np.uint8)
        metrics = sdvi.compare(from_file, rgb)
        check(metrics["psnr_db"] > 40, f"an image against its own 8-bit render: {metrics}")
        raster = sdvi.read_raster(str(inputs / "a.png"))
        check(raster.shape == (72, 96, 3) and raster.dtype == np.float32, f"read_raster shape {raster.shape}")
        image_file, _ = sdvi.vectorize(str(inputs / "a.png"))
        image_array, report = sdvi.vectorize(raster.astype(np.uint8))
        check(np.array_equal(image_file.vertices, image_array.vertices) and
              np.array_equal(image_file.triangles, image_array.triangles),
              "vectorizing an 8-bit array equals vectorizing its PNG")
        check(report["triangles"] == image_array.triangle_count, "report matches the image")
        # The report's metrics are the file's, as `sdvi compare FILE.sdvi SOURCE` prints them.
        _, report = sdvi.vectorize(str(inputs / "a.png"), str(tmp / "a_py.sdvi"))
        printed = json.loads(subprocess.run([cli, "compare", str(tmp / "a_py.sdvi"), str(inputs / "a.png"), "--json"],
                                            check=True, capture_output=True, text=True).stdout)
        check((report["psnr_db"], report["mssim"], report["mean_error"]) ==
              (printed["psnr"], printed["mssim"], printed["mean_error"]),
              f"report {report} against compare {printed}")
        # The report is the command's, field for field, apart from names and times.
        cli_report = json.loads(subprocess.run([cli, "vectorize", str(inputs / "a.png"), "-o", str(tmp / "a_cli.sdvi"),
                                                "--json"], check=True, capture_output=True, text=True).stdout)

        def timeless(r):
            r = {k: v for k, v in r.items() if k not in ("input", "output", "time_s", "phases_s")}
            r["history"] = [{k: v for k, v in h.items() if k != "time_s"} for h in r["history"]]
            return r
        check(timeless(report) == timeless(cli_report), f"report {report} against the command's {cli_report}")
        check(report["output"] == str(tmp / "a_py.sdvi"), f"report names the output: {report['output']}")
        # compress with a reference: the file of `sdvi compress --reference`.
        size = sdvi.compress(str(tmp / "a_py.sdvi"), str(tmp / "a_rd_py.sdvi"), reference=str(inputs / "a.png"))
        subprocess.run([cli, "compress", str(tmp / "a_py.sdvi"), "-o", str(tmp / "a_rd_cli.sdvi"), "--reference",
                        str(inputs / "a.png"), "--quiet"], check=True)
        check((tmp / "a_rd_py.sdvi").read_bytes() == (tmp / "a_rd_cli.sdvi").read_bytes() and
              size < (tmp / "a_py.sdvi").stat().st_size, "compress(reference=...) differs from the command's")
        try:
            sdvi.vectorize(np.zeros((4, 4, 7), np.uint8))
            check(False, "a 7-channel array is refused")
        except ValueError as error:
            check("1..4 channels" in str(error), f"error text: {error}")
        try:
            sdvi.load(str(inputs / "broken.png"))
            check(False, "a non-sdvi file is refused")
        except Exception as error:
            check("broken.png" in str(error), f"error names the file: {error}")
    print("ok")


if __name__ == "__main__":
    main()
