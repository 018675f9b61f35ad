"""Batches of brdfbake tables across a Dask cluster (``dask.distributed``).

:func:`bake` takes a list of jobs, materials or environments and a ``distributed.Client`` and bakes
them on the cluster's workers. Each worker process opens its device once, on its first task, and
reuses it (one device per worker: start one single-threaded worker per GPU, with
``BRDFBAKE_DEVICE`` naming it, and give GPU workers a resource such as ``--resources GPU=1`` that
``resources={"GPU": 1}`` asks for). Results are written atomically under a shared output root, or
returned as arrays; a failure is reported for its item without losing the others; progress shows in
Dask's dashboard (tasks named ``brdfbake-<kind>``) and, with ``progress=True``, in Dask's progress
bar.

The same code runs on a laptop's ``LocalCluster``, on an HPC scheduler through dask-jobqueue
(``SLURMCluster``, ``PBSCluster``, ...) or on Kubernetes through dask-kubernetes: only the cluster
object changes (docs/PYTHON.md, "Running on a cluster").

>>> from distributed import Client, LocalCluster
>>> import brdfbake.dask
>>> with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as client:
...     materials = [{"name": f"rough{r:.2f}", "model": "gltf", "roughness": r} for r in (0.1, 0.5, 0.9)]
...     batch = brdfbake.dask.bake(client, materials, kind="tabulate", layout="merl", output_root="merl")
>>> batch.failed
[]
"""

from __future__ import annotations

import json
import os
import shutil
import socket
import tempfile
import time
import warnings
from typing import Any, Dict, Iterable, List, Optional, Sequence

import numpy as np

import brdfbake

from ._api import _FAMILY_OF_KIND, _to_json
from ._errors import BakeWarning, InputError

__all__ = ["Outcome", "Batch", "bake", "submit", "collect", "DevicePlugin", "sweep"]


# ---- Outcomes ----------------------------------------------------------------------------------------


class Outcome:
    """What became of one item of a batch.

    ``ok`` says whether it was baked. ``value`` is, for a job, its manifest (a dict); for a table
    written under the output root, ``{"path": ..., "meta": ...}``; for a table returned,
    ``{"array": ..., "meta": ...}``; for an item of a .npy shard, ``{"path": shard, "index": i,
    "meta": ...}``. A failed item has ``error`` (the one-line message) and ``error_type`` (e.g.
    ``"InputError"``, or ``"KilledWorker"`` when its worker died).
    """

    __slots__ = ("name", "ok", "value", "error", "error_type", "worker", "seconds")

    def __init__(self, name: str, ok: bool, value: Any = None, error: Optional[str] = None,
                 error_type: Optional[str] = None, worker: Optional[str] = None, seconds: float = 0.0):
        self.name, self.ok, self.value = name, ok, value
        self.error, self.error_type, self.worker, self.seconds = error, error_type, worker, seconds

    def __repr__(self) -> str:
        if self.ok:
            return f"<Outcome {self.name}: ok ({self.seconds:.3f} s on {self.worker})>"
        return f"<Outcome {self.name}: {self.error_type}: {self.error}>"


class Batch(list):
    """The outcomes of a batch, in the order of its items."""

    seconds: float = 0.0  # wall time of the whole batch: from submission (bake) or waiting (collect) to the last result

    @property
    def succeeded(self) -> List[Outcome]:
        return [o for o in self if o.ok]

    @property
    def failed(self) -> List[Outcome]:
        return [o for o in self if not o.ok]

    def by_name(self) -> Dict[str, Outcome]:
        return {o.name: o for o in self}

    def raise_for_failures(self) -> "Batch":
        """Raises brdfbake.Error listing every failed item, if any failed; returns the batch."""
        if self.failed:
            lines = "; ".join(f"{o.name}: {o.error}" for o in self.failed[:10])
            more = f" (and {len(self.failed) - 10} more)" if len(self.failed) > 10 else ""
            raise brdfbake.Error(f"{len(self.failed)} of {len(self)} items failed: {lines}{more}")
        return self

    def __repr__(self) -> str:
        return f"<brdfbake.dask.Batch: {len(self.succeeded)} of {len(self)} baked, {len(self.failed)} failed, " \
               f"{self.seconds:.2f} s>"


# ---- Work on the workers -------------------------------------------------------------------------


def _atomic_write(path: str, write) -> None:
    """Writes through `write(file)` into a temporary file beside `path`, then renames it into place."""
    folder = os.path.dirname(path) or "."
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _plain(meta: Dict[str, Any]) -> Dict[str, Any]:
    """Metadata as plain JSON values."""
    return json.loads(json.dumps(meta, default=lambda o: o.tolist() if isinstance(o, np.ndarray) else str(o)))


def _array_copy(result: "brdfbake.Result"):
    a = result.array
    if isinstance(a, list):
        return [np.array(level) for level in a]
    return np.array(a)


def _bake_one(kind: Optional[str], item: Any, params: Dict[str, Any], device: Optional[str],
              output_root: Optional[str], name: str):
    """Bakes one item on this worker; returns (value, result) (result None for jobs)."""
    if kind is None:
        folder = os.path.join(output_root, name)  # type: ignore[arg-type]
        return brdfbake.run(item, folder), None
    family = _FAMILY_OF_KIND[kind]
    args = dict(params)
    if device is not None:
        args["device"] = device
    if len(family.kinds) > 1:
        args["kind"] = kind
    if family.uses_environment:
        return None, brdfbake.function_of(kind)(item, **args)
    if family.takes_material:
        if family.is_eval:
            return None, brdfbake.function_of(kind)(item, args.pop("wi"), args.pop("wo"), **args)
        return None, brdfbake.function_of(kind)(item, **args)
    if not isinstance(item, dict):
        raise InputError(f"{kind} items must be dicts of parameters (got {type(item).__name__})")
    return None, brdfbake.function_of(kind)(**{**args, **item})


def _run_group(kind: Optional[str], group: Sequence[tuple], params: Dict[str, Any], device: Optional[str],
               output_root: Optional[str], output_format: Optional[str], suffix: str,
               shard: Optional[str]) -> List[Dict[str, Any]]:
    """A task: bakes a group of (name, item) on this worker, each failure caught and reported alone."""
    worker = socket.gethostname() + ":" + str(os.getpid())
    outcomes: List[Dict[str, Any]] = []
    stack: List[np.ndarray] = []
    for name, item in group:
        t0 = time.perf_counter()
        try:
            value, result = _bake_one(kind, item, params, device, output_root, name)
            if result is not None:
                meta = _plain(result.meta)
                if output_format == "npy" and shard is not None:
                    a = result.array
                    if isinstance(a, list):
                        raise InputError(f"{kind}: a cube cannot go into an .npy shard (write it to a file)")
                    stack.append(np.asarray(a, dtype=np.float32))
                    value = {"path": os.path.join(output_root, shard + ".npy"), "index": len(stack) - 1,
                             "meta": meta}
                elif output_format == "npy":
                    a = result.array
                    if isinstance(a, list):
                        raise InputError(f"{kind}: a cube cannot be written as .npy (write it to a file)")
                    path = os.path.join(output_root, name + ".npy")
                    _atomic_write(path, lambda f: np.save(f, np.asarray(a, dtype=np.float32)))
                    _atomic_write(os.path.join(output_root, name + ".json"),
                                  lambda f: f.write(json.dumps(meta, indent=2).encode()))
                    value = {"path": path, "meta": meta}
                elif output_root is not None:
                    value = {"path": result.save(os.path.join(output_root, name + suffix)), "meta": meta}
                else:
                    value = {"array": _array_copy(result), "meta": meta}
            outcomes.append({"name": name, "ok": True, "value": value, "worker": worker,
                             "seconds": time.perf_counter() - t0})
        except Exception as e:  # reported for this item; the others go on
            outcomes.append({"name": name, "ok": False, "error": str(e), "error_type": type(e).__name__,
                             "worker": worker, "seconds": time.perf_counter() - t0})
    if shard is not None and stack:
        shard_path = os.path.join(output_root, shard + ".npy")  # type: ignore[arg-type]
        index = [{"name": o["name"], "index": o["value"]["index"], "meta": o["value"]["meta"]}
                 for o in outcomes if o["ok"]]
        _atomic_write(shard_path, lambda f: np.save(f, np.stack(stack)))
        _atomic_write(os.path.join(output_root, shard + ".json"),  # type: ignore[arg-type]
                      lambda f: f.write(json.dumps({"items": index}, indent=2).encode()))
    return outcomes


# ---- Submission ----------------------------------------------------------------------------------


def _default_name(kind: Optional[str], item: Any, i: int) -> str:
    if kind is None:
        return f"job-{i:05d}"
    family = _FAMILY_OF_KIND[kind]
    if family.takes_material and isinstance(item, dict) and isinstance(item.get("name"), str):
        return item["name"]
    if family.takes_material and isinstance(item, (str, os.PathLike)):
        return os.path.splitext(os.path.basename(os.fspath(item)))[0]
    if family.uses_environment and isinstance(item, (str, os.PathLike)):
        base = os.path.basename(os.fspath(item)).replace("builtin:", "")
        return os.path.splitext(base)[0] or f"env-{i:05d}"
    return f"{kind}-{i:05d}"


def _check_names(names: List[str]) -> None:
    seen = set()
    for n in names:
        if not isinstance(n, str) or not n or "/" in n or "\\" in n or n in (".", ".."):
            raise InputError(f"brdfbake.dask: item name {n!r} cannot be a file name")
        if n in seen:
            raise InputError(f"brdfbake.dask: two items are named {n!r}; give names=[...]")
        seen.add(n)


# A batch that will write more than this is announced with its estimate (a BakeWarning) before it
# starts: 64 MERL tables are 2.1 GiB, 1000 are 33 GiB.
LARGE_OUTPUT_BYTES = 1 << 30
_MERL_VALUES = 90 * 90 * 180 * 3


def _table_bytes(kind: str, resolved: Dict[str, Any], output_format: Optional[str]) -> Optional[int]:
    """The bytes one table of the batch writes (`resolved`: the request brdfbake.validate returns), where the kind's size is known before baking (MERL
    tables: 90 x 90 x 180 x 3 doubles after MERL's three int32 dimensions, floats in .npy); None
    otherwise."""
    if kind == "tabulate" and resolved.get("parameters", {}).get("layout") == "merl":
        return _MERL_VALUES * 4 + 128 if output_format == "npy" else _MERL_VALUES * 8 + 12  # + the headers
    return None


def _gib(n: float) -> str:
    return f"{n / (1 << 30):.1f} GiB" if n >= (1 << 30) else f"{n / (1 << 20):.0f} MiB"


def _check_output_size(per_table: Optional[int], count: int, output_root: str) -> None:
    """Refuses a batch whose estimated output exceeds the free space under output_root, and warns
    (BakeWarning) above LARGE_OUTPUT_BYTES, before anything is baked."""
    if per_table is None or count == 0:
        return
    total = per_table * count
    free = shutil.disk_usage(output_root).free
    what = f"{count} tables of {_gib(per_table)}, about {_gib(total)} under {output_root}"
    if total > free:
        raise InputError(f"brdfbake.dask: {what}, but only {_gib(free)} is free there: bake fewer items, or "
                         f"write to a larger disk")
    if total > LARGE_OUTPUT_BYTES:
        warnings.warn(f"brdfbake.dask: {what} ({_gib(free)} free)", BakeWarning, stacklevel=4)


def submit(client, items: Iterable[Any], *, kind: Optional[str] = None, output_root: Optional[str] = None,
           names: Optional[Sequence[str]] = None, output_format: Optional[str] = None,
           suffix: Optional[str] = None, batch_size: int = 1, shard_size: Optional[int] = None,
           resources: Optional[Dict[str, float]] = None, device: Optional[str] = None, retries: int = 0,
           **params: Any):
    """Submits a batch without waiting: returns ``(names, futures, groups)`` for :func:`collect`.
    The arguments are those of :func:`bake` (with ``client=None`` the batch is baked at once, in
    this process, and its :class:`Batch` stands in place of the futures)."""
    items = list(items)
    if kind is not None and kind not in _FAMILY_OF_KIND:
        raise InputError(f"brdfbake.dask: unknown table kind {kind!r} (known: {', '.join(_FAMILY_OF_KIND)})")
    if kind is None and params:
        raise InputError(f"brdfbake.dask: jobs carry their own parameters (got {', '.join(params)})")
    if kind is None and output_root is None:
        raise InputError("brdfbake.dask: jobs are written to files: give output_root")
    if output_format not in (None, "npy"):
        raise InputError(f"brdfbake.dask: output_format must be None (the kind's own files) or 'npy' "
                         f"(got {output_format!r})")
    if output_format == "npy" and (kind is None or output_root is None):
        raise InputError("brdfbake.dask: output_format='npy' is for tables written under output_root")
    if shard_size is not None:
        if output_format != "npy" or not isinstance(shard_size, int) or shard_size < 1:
            raise InputError("brdfbake.dask: shard_size (a positive integer) goes with output_format='npy'")
        batch_size = shard_size
    if not isinstance(batch_size, int) or batch_size < 1:
        raise InputError(f"brdfbake.dask: batch_size must be a positive integer (got {batch_size!r})")
    names = list(names) if names is not None else [_default_name(kind, it, i) for i, it in enumerate(items)]
    if len(names) != len(items):
        raise InputError(f"brdfbake.dask: {len(names)} names for {len(items)} items")
    _check_names(names)
    if kind is not None:
        # Checked here, before anything is submitted: the shared parameters of the kind.
        probe = {k: v for k, v in params.items() if k not in ("wi", "wo")}
        family = _FAMILY_OF_KIND[kind]
        if not family.takes_material and not family.uses_environment and items and isinstance(items[0], dict):
            probe.update(items[0])
        if family.takes_material and items:
            probe["material"] = items[0]
        resolved = brdfbake.validate(kind, **probe)
        if suffix is None:
            suffix = os.path.splitext(resolved["output"])[1]
    if output_root is not None:
        output_root = os.path.abspath(os.fspath(output_root))
        os.makedirs(output_root, exist_ok=True)
        if kind is not None:
            _check_output_size(_table_bytes(kind, resolved, output_format), len(items), output_root)
    label = "job" if kind is None else kind
    groups = [list(zip(names[i:i + batch_size], items[i:i + batch_size])) for i in range(0, len(items), batch_size)]
    if client is None:
        # No cluster: the same tasks, one after the other in this process (the baseline, or a laptop).
        t0 = time.perf_counter()
        outcomes = []
        for g, group in enumerate(groups):
            shard = f"shard-{g:05d}" if shard_size is not None else None
            for o in _run_group(kind, group, params, device, output_root, output_format, suffix or "", shard):
                outcomes.append(Outcome(o["name"], o["ok"], o.get("value"), o.get("error"), o.get("error_type"),
                                        o.get("worker"), o.get("seconds", 0.0)))
        batch = Batch(outcomes)
        batch.seconds = time.perf_counter() - t0
        return names, batch, groups
    futures = []
    for g, group in enumerate(groups):
        shard = f"shard-{g:05d}" if shard_size is not None else None
        key = f"brdfbake-{label}-{group[0][0]}-{os.urandom(4).hex()}"
        futures.append(client.submit(_run_group, kind, group, params, device, output_root, output_format,
                                     suffix or "", shard, key=key, resources=resources, retries=retries,
                                     pure=False))
    return names, futures, groups


def collect(names: Sequence[str], futures, groups, *, progress: bool = False) -> Batch:
    """Waits for submitted futures and returns the outcomes in the order of the items."""
    from distributed import progress as dask_progress
    from distributed import wait

    t0 = time.perf_counter()
    if progress:
        dask_progress(futures)
    wait(futures)
    by_name: Dict[str, Outcome] = {}
    for future, group in zip(futures, groups):
        try:
            for o in future.result():
                by_name[o["name"]] = Outcome(o["name"], o["ok"], o.get("value"), o.get("error"),
                                             o.get("error_type"), o.get("worker"), o.get("seconds", 0.0))
        except Exception as e:  # the task itself failed (its worker died, it was cancelled)
            for name, _ in group:
                by_name[name] = Outcome(name, False, error=str(e) or type(e).__name__, error_type=type(e).__name__)
    batch = Batch(by_name[n] for n in names)
    batch.seconds = time.perf_counter() - t0
    return batch


def bake(client, items: Iterable[Any], *, kind: Optional[str] = None, output_root: Optional[str] = None,
         names: Optional[Sequence[str]] = None, output_format: Optional[str] = None, suffix: Optional[str] = None,
         batch_size: int = 1, shard_size: Optional[int] = None, resources: Optional[Dict[str, float]] = None,
         device: Optional[str] = None, retries: int = 0, progress: bool = False, **params: Any) -> Batch:
    """Bakes every item on the cluster of ``client`` and returns their outcomes (a :class:`Batch`).
    With ``client=None`` the same tasks run one after the other in this process (same files, same
    outcomes: the single-process baseline, or a machine without a cluster).

    ``items`` are, with ``kind=None``, jobs (dicts, job files or JSON text; docs/SCENES.md), each run
    into ``output_root/<name>`` as ``brdfbake.run`` does (all or nothing, manifest.json last). With
    a ``kind`` they are what varies from table to table: materials (dicts or files) for
    ``tabulate`` and ``eval`` (``eval`` takes ``wi`` and ``wo`` among ``params``), environments
    (paths or float arrays) for ``prefilter`` and ``irradiance``, dicts of parameters for the other
    kinds; ``params`` are the kind's arguments shared by every item (those of ``brdfbake.<function>``).

    Output: with ``output_root``, each table is written atomically to ``output_root/<name><suffix>``
    by the command-line tool's writers (``suffix`` defaults to the kind's own extension, e.g.
    ``.binary`` for MERL tables), or with ``output_format="npy"`` as a float32 ``<name>.npy`` with
    ``<name>.json`` (its metadata); ``shard_size=k`` packs k tables into each ``shard-NNNNN.npy``
    (shape (k, ...)) with a ``shard-NNNNN.json`` index. Without ``output_root`` the arrays come back
    in the outcomes (mind the client's memory for large batches).

    ``names`` name the items (default: the material's ``name``, the file's stem, or
    ``<kind>-NNNNN``); ``batch_size`` items go into one task; ``resources`` (e.g. ``{"GPU": 1}``)
    restricts tasks to workers that declared them; ``device`` is the selector every worker uses
    (default: the worker's ``BRDFBAKE_DEVICE``, else its default device); ``retries`` re-runs tasks
    whose worker died; ``progress=True`` shows Dask's progress bar.

    A failed item is reported in its :class:`Outcome` (``batch.failed``) and the others go on;
    ``batch.raise_for_failures()`` turns failures into an exception.
    """
    t0 = time.perf_counter()
    names_, futures, groups = submit(client, items, kind=kind, output_root=output_root, names=names,
                                     output_format=output_format, suffix=suffix, batch_size=batch_size,
                                     shard_size=shard_size, resources=resources, device=device,
                                     retries=retries, **params)
    batch = futures if client is None else collect(names_, futures, groups, progress=progress)
    batch.seconds = time.perf_counter() - t0  # submission included
    return batch


# ---- Sweeps of bake settings over environments ------------------------------------------------------


def _setting_label(options: Dict[str, Any]) -> str:
    """``chain_size=64``: the options by their canonical names (an alias such as ``cube_size`` is
    named as its option, as everything the package writes names it)."""
    aliases = {a[2:].replace("-", "_"): o["name"] for o in brdfbake.plan_options() for a in o.get("aliases", [])}
    return ",".join(f"{aliases.get(k, k)}={v}" for k, v in options.items()) or "default"


def _file_sizes(folder: str) -> Dict[str, int]:
    sizes = {}
    for root, _, names in os.walk(folder):
        for n in names:
            path = os.path.join(root, n)
            sizes[os.path.relpath(path, folder)] = os.path.getsize(path)
    return dict(sorted(sizes.items()))


def _sphere_errors(split: np.ndarray, ref: np.ndarray, spheres: List[Dict[str, Any]]) -> List[Dict[str, float]]:
    """Per sphere, as the library's preview computes it: per pixel |split - ref| / |ref| (RGB norms,
    in double from the float32 renders), its RMS, 99th percentile (the sorted errors' element
    (n - 1) * 99 // 100) and max."""
    h, w = split.shape[:2]
    ys, xs = np.mgrid[0:h, 0:w]
    dist = np.linalg.norm(split.astype(np.float64) - ref.astype(np.float64), axis=2)
    norm = np.linalg.norm(ref.astype(np.float64), axis=2)
    out = []
    for sphere in spheres:
        cx, cy = sphere["centre"]
        inside = (xs + 0.5 - cx) ** 2 + (ys + 0.5 - cy) ** 2 < sphere["radius"] ** 2
        d, n = dist[inside], norm[inside]
        with np.errstate(divide="ignore", invalid="ignore"):
            e = np.where(n > 0, d / n, np.where(d > 0, 1.0, 0.0))
        e = np.sort(e)
        out.append({"rms": float(np.sqrt(np.mean(e * e))), "p99": float(e[(len(e) - 1) * 99 // 100]),
                    "max": float(e[-1])})
    return out


def _sweep_env(env: str, name: str, labelled: Sequence[tuple], target: str, width: int, height: int,
               device: Optional[str], runs: int, shares: bool = True) -> List[Dict[str, Any]]:
    """One environment's rows (runs on a worker): each setting baked as ``brdfbake.bake_scene`` bakes
    it, its split-sum render compared with the reference render; with ``shares`` each setting's
    preview renders its reference and its files' ideal bake, whose engine and bake shares (the
    preview's JSON's) go into the row; without, the reference is rendered once for the environment
    (again only for a setting that changes the target's BRDF)."""
    try:
        from distributed import get_worker
        worker = get_worker().address
    except (ImportError, ValueError):
        worker = socket.gethostname()
    dev = {} if device is None else {"device": device}
    references: Dict[str, Dict[str, Any]] = {}
    rows = []
    tmp = tempfile.mkdtemp(prefix="brdfbake-sweep-")
    try:
        for i, (label, options) in enumerate(labelled):
            row: Dict[str, Any] = {"env": name, "setting": label, "target": target, "options": dict(options),
                                   "worker": worker}
            folder = os.path.join(tmp, f"setting-{i}")
            try:
                times = []
                for _ in range(runs):
                    shutil.rmtree(folder, ignore_errors=True)
                    t0 = time.perf_counter()
                    brdfbake.bake_scene(None, folder, env=env, target=target, **dev, **options)
                    times.append(time.perf_counter() - t0)
                row["seconds"] = float(np.median(times))
                row["file_sizes"] = _file_sizes(folder)
                row["bytes"], row["files"] = sum(row["file_sizes"].values()), len(row["file_sizes"])
                look = dict(target=target, bake=folder, width=width, height=height, **dev)
                # With shares: the whole preview of these files, its own reference and the ideal bake's
                # render that splits the error (docs/PREVIEW.md, "Engine share and bake share");
                # without, the split-sum render alone against the environment's reference, rendered once.
                split = brdfbake.preview(env, reference=shares, shares=shares, **look).preview
                ref = split if shares else references.get(split["brdf"])
                if shares:
                    row["reference_seconds"] = split["times"]["reference"]
                elif ref is None:
                    t0 = time.perf_counter()
                    ref = references[split["brdf"]] = brdfbake.preview(env, shares=False, **look).preview
                    row["reference_seconds"] = time.perf_counter() - t0
                errors = _sphere_errors(split["splitsum"], ref["reference"], split["spheres"])
                if shares:  # each sphere's shares as the preview's JSON gives them (spheres[k].engine_share, ...)
                    for e, sphere in zip(errors, split["spheres"]):
                        e["engine_share"] = dict(sphere["engine_share"])
                        e["bake_share"] = dict(sphere["bake_share"])
                # the median over the spheres of each figure's RMS, and over each group's
                figures = {"error": [e["rms"] for e in errors]}
                if shares:
                    figures["engine_share"] = [e["engine_share"]["rms"] for e in errors]
                    figures["bake_share"] = [e["bake_share"]["rms"] for e in errors]
                group_of = [sphere["name"].split(" ")[0] for sphere in split["spheres"]]
                for figure, values in figures.items():
                    row[figure] = float(np.median(values))
                    groups: Dict[str, List[float]] = {}
                    for g, v in zip(group_of, values):
                        groups.setdefault(g, []).append(v)
                    for g, v in groups.items():
                        row[f"{figure}_{g}"] = float(np.median(v))
                row["spheres"] = [{"name": s["name"], **e} for s, e in zip(split["spheres"], errors)]
            except brdfbake.Error as e:
                row["failed"] = f"{type(e).__name__}: {e}"
            finally:
                shutil.rmtree(folder, ignore_errors=True)
            rows.append(row)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return rows


def sweep(client, envs: Iterable[Any], settings: Any = None, *, target: str = "generic", width: int = 128,
          height: int = 128, runs: int = 1, device: Optional[str] = None, shares: bool = True,
          resources: Optional[Dict[str, float]] = None, retries: int = 0,
          progress: bool = False) -> List[Dict[str, Any]]:
    """What each bake setting costs under many environments, at the level of the render (the
    cluster form of ``brdfbake report --kinds bake``, docs/REPORT.md): for every environment and
    setting, the whole bake's wall time (``brdfbake.bake_scene`` into a temporary folder, the median
    of ``runs``), the bytes it wrote, and the preview's split-sum render of its files (the default
    grid at ``width`` x ``height``) against the reference render, and how that error splits into the
    engine's share and the bake's.

    ``envs`` are environment paths (a path every worker can read) or ``builtin:NAME``. ``settings``
    are :func:`brdfbake.bake_scene` options, a list of dicts (``[{}, {"chain_size": 64}]``; ``{}`` is
    the target's default) or a dict ``{label: options}``; default: the target's default alone. One
    task per environment (named ``brdfbake-sweep-<env>``) bakes its settings one after the other, so
    the times are not shared between tasks (and, with ``shares=False``, the reference is rendered
    once); ``client=None`` runs them in this process.

    Returns one dict per environment and setting, in the order given: ``env``, ``setting`` (its
    label), ``target``, ``options``, ``seconds``, ``bytes`` and ``files`` (every file the bake wrote,
    manifest.json included; ``file_sizes`` each), ``error`` (the median over
    the spheres of their relative RMS error, split-sum vs reference, in linear radiance),
    ``error_<group>`` (the median over each row of the grid: ``white``, ``grey``, ``dark``,
    ``gold``, ``copper``, ``silver``), ``engine_share`` and ``bake_share`` (the error's shares,
    docs/PREVIEW.md "Engine share and bake share": the median over the spheres of the RMS of
    \|ideal - reference\| / \|reference\|, what the target's shader does with perfect files, and of
    \|split-sum - ideal\| / \|reference\|, what these files add; as the preview's JSON gives them per
    sphere), ``engine_share_<group>`` and ``bake_share_<group>``, ``spheres`` (each sphere's ``rms``,
    ``p99``, ``max``, and its ``engine_share`` and ``bake_share``, each ``rms``, ``p99``, ``max``),
    ``worker``, and ``reference_seconds`` on each row that rendered a reference: every row with
    shares (each setting's preview renders its reference and its ideal bake), else the first row of
    an environment (its reference serves the others). ``shares=False`` leaves the shares out, and
    with them each setting's ideal bake (a few seconds: the chain filtered again at a high face size)
    and its reference render. A setting that fails has ``failed`` (the
    message) instead of the numbers; the others go on. ``pandas.DataFrame(rows)`` makes a table of them.
    """
    if isinstance(settings, dict):
        labelled = [(str(k), dict(v)) for k, v in settings.items()]
    else:
        labelled = [(_setting_label(dict(o)), dict(o)) for o in (settings if settings is not None else [{}])]
    if not labelled:
        raise InputError("sweep.settings: give at least one setting ({} is the target's default)")
    own_arguments = {"target": "give target= to sweep()", "env": "give the environments as envs",
                     "environment": "give the environments as envs",
                     "scene": "a sweep bakes the default grid's materials", "output_dir": "a sweep bakes into "
                     "temporary folders of its own"}
    for label, o in labelled:
        # the sweep's own arguments, not a setting's: a setting naming one aborted every row
        for name, why in own_arguments.items():
            if name in o:
                raise InputError(f"sweep.settings[{label!r}].{name}: not a setting of a sweep ({why})")
    if isinstance(envs, (str, os.PathLike)):
        envs = [envs]  # one environment, not one a character
    envs = list(envs)
    if not envs:
        raise InputError("sweep.envs: give at least one environment")
    for e in envs:
        if not isinstance(e, (str, os.PathLike)):
            raise InputError(f"sweep.envs: environment paths or builtin:NAME (got {type(e).__name__})")
    if not isinstance(runs, int) or runs < 1:
        raise InputError(f"sweep.runs: must be a count >= 1 (got {runs!r})")
    names = [os.path.splitext(os.path.basename(os.fspath(e)))[0] if not os.fspath(e).startswith("builtin:")
             else os.fspath(e) for e in envs]
    args = [(os.fspath(e), n, labelled, target, int(width), int(height), device, runs, bool(shares))
            for e, n in zip(envs, names)]
    if client is None:
        rows = []
        for a in args:
            rows.extend(_sweep_env(*a))
        return rows
    futures = [client.submit(_sweep_env, *a, key=f"brdfbake-sweep-{i:05d}-{n}", pure=False, resources=resources,
                             retries=retries) for i, (a, n) in enumerate(zip(args, names))]
    if progress:
        from distributed import progress as dask_progress
        dask_progress(futures)
    rows = []
    for f, a in zip(futures, args):
        try:
            rows.extend(f.result())
        except Exception as e:  # the task itself failed (its worker died)
            rows.extend({"env": a[1], "setting": label, "target": target, "options": dict(o),
                         "failed": f"{type(e).__name__}: {e}"} for label, o in labelled)
    return rows


# ---- Workers -------------------------------------------------------------------------------------

try:
    from distributed.diagnostics.plugin import WorkerPlugin as _WorkerPlugin
except ImportError:  # distributed is optional until this module is used with a cluster
    _WorkerPlugin = object  # type: ignore[assignment,misc]


class DevicePlugin(_WorkerPlugin):  # type: ignore[misc,valid-type]
    """Opens each worker's device when the worker starts (``client.register_plugin(DevicePlugin())``),
    so that a worker without a usable device fails at once rather than at its first task, and the
    device's start-up is not counted in the first task. ``device`` sets the selector of every worker
    (default: each worker's own ``BRDFBAKE_DEVICE``, else its default device)."""

    name = "brdfbake-device"

    def __init__(self, device: Optional[str] = None):
        self.device = device

    def setup(self, worker) -> None:
        if self.device is not None:
            os.environ["BRDFBAKE_DEVICE"] = self.device
        from . import _brdfbake

        _brdfbake.open_backend(self.device or "")
