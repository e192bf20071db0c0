# SPDX-License-Identifier: GPL-3.0-or-later
"""Many files over a Dask cluster: ``map_files`` maps input files to output files with one
of the ``sdvi`` commands, one task per file.

* Same bytes as the command: a task calls the binding, which makes the library calls that
  ``sdvi vectorize|render|compress IN -o OUT`` makes with the same options, and results do
  not depend on the thread count.
* Resumable: outputs are written atomically (temporary file, then rename), so an output
  that exists is complete; with ``resume=True`` (default) its input is skipped.
* One failing input is reported (``status: "failed"`` with the error text naming the file)
  and the others go on.
* A JSON-lines report gets one line per input as it finishes: input, output, status
  (``ok``, ``skipped``, ``failed``), seconds, worker, error, and for vectorize the
  command's report fields (triangles, PSNR, ...).

Workers need the ``sdvi`` package importable (see the README, "Python and Dask") and the
input and output paths visible under the same names (a shared file system).
"""

import glob
import json
import os
import socket
import time
from pathlib import Path

# Output file extension per command.
COMMANDS = {"vectorize": ".sdvi", "render": ".png", "compress": ".sdvi"}
IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp"}


def expand_inputs(inputs, command="vectorize"):
    """A list of files from a directory, a glob pattern, a file or a list of those; sorted
    within each directory or pattern. Directories give the files the command reads."""
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    suffixes = IMAGE_SUFFIXES if command == "vectorize" else {".sdvi"}
    files = []
    for item in inputs:
        path = Path(item)
        if path.is_dir():
            files += sorted(str(p) for p in path.iterdir() if p.is_file() and p.suffix.lower() in suffixes)
        elif any(ch in str(item) for ch in "*?["):
            files += sorted(p for p in glob.glob(str(item)) if os.path.isfile(p))
        else:
            files.append(str(item))
    return files


def output_for(input_path, output_dir, command):
    """The output of input_path: output_dir / (input stem + the command's extension)."""
    return str(Path(output_dir) / (Path(input_path).stem + COMMANDS[command]))


def run_one(command, input_path, output_path, options, resume=True):
    """One task (runs on a worker): returns the report record of input_path."""
    record = {"input": input_path, "output": output_path, "command": command,
              "worker": socket.gethostname(), "pid": os.getpid()}
    if resume and os.path.exists(output_path):
        record.update(status="skipped", seconds=0.0)
        return record
    import sdvi  # imported on the worker

    start = time.monotonic()
    try:
        if command == "vectorize":
            _, report = sdvi.vectorize(input_path, output_path, **options)
            record["report"] = report
        elif command == "render":
            sdvi.render(input_path, output_path, **options)
        elif command == "compress":
            record["bytes"] = sdvi.compress(input_path, output_path, **options)
        else:
            raise ValueError(f"unknown command {command!r}")
        record["status"] = "ok"
    except Exception as error:  # reported, the other inputs go on
        record["status"] = "failed"
        record["error"] = f"{input_path}: {error}"
    record["seconds"] = time.monotonic() - start
    return record


def map_files(client, inputs, output_dir, command="vectorize", options=None, resume=True,
              report=None, on_done=None):
    """Runs ``command`` on every input over the Dask ``client``; returns the records in input
    order. ``report`` (a path) gets the JSON lines (appended, one per input as it finishes);
    ``on_done(record, finished, total)`` is called as each finishes (a progress bar)."""
    from distributed import as_completed

    if command not in COMMANDS:
        raise ValueError(f"command must be one of {sorted(COMMANDS)}, got {command!r}")
    files = expand_inputs(inputs, command)
    outputs = [output_for(f, output_dir, command) for f in files]
    seen = {}
    for f, out in zip(files, outputs):
        if out in seen:
            raise ValueError(f"{f} and {seen[out]} would both write {out}")
        seen[out] = f
    os.makedirs(output_dir, exist_ok=True)
    options = dict(options or {})
    # pure=False: a fresh key per call, so a rerun never gets an earlier run's result back.
    futures = [client.submit(run_one, command, f, out, options, resume, pure=False)
               for f, out in zip(files, outputs)]
    index = {future.key: i for i, future in enumerate(futures)}
    records = [None] * len(futures)
    log = open(report, "a", encoding="utf-8") if report else None
    try:
        for finished, future in enumerate(as_completed(futures), start=1):
            try:
                record = future.result()
            except Exception as error:  # the task's worker died (memory limit), cancelled, ...
                i = index[future.key]
                record = {"input": files[i], "output": outputs[i], "command": command, "status": "failed",
                          "error": f"{files[i]}: {type(error).__name__}: {error}"}
            records[index[future.key]] = record
            if log:
                log.write(json.dumps(record, sort_keys=True) + "\n")
                log.flush()
            if on_done:
                on_done(record, finished, len(futures))
    finally:
        if log:
            log.close()
    return records
