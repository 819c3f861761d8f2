#!/usr/bin/env python3
"""Spreads a batch of glint renders over a Dask cluster (a local one by default).

Each task renders a chunk of jobs of one scene with glint.render_batch and writes EXRs with
their AOVs; the scene is loaded once per worker process (cached in the worker), not once per
job. On a real cluster, pass the scheduler's address (``--scheduler tcp://host:8786``) and make
the scene and output folder visible to every worker (a shared file system).

    pip install "dask[distributed]"
    python python/examples/dask_batch.py --jobs 16 --out /tmp/turntable [SCENE.glb]

The same shape works with Ray: decorate ``render_chunk`` with ``@ray.remote`` and collect
``ray.get([render_chunk.remote(...) for chunk in chunks])``.
"""

import argparse
import math
from pathlib import Path

_scenes = {}


def _scene(path):
    """The worker's loaded scene for `path` (None: the demo), loaded on first use."""
    import glint

    if path not in _scenes:
        _scenes[path] = glint.load(path)
    return _scenes[path]


def render_chunk(scene_path, jobs, threads):
    """Renders `jobs` (dicts of Scene.render arguments) of one scene on this worker."""
    import glint

    scene = _scene(scene_path)
    results = glint.render_batch([dict(job, scene=scene) for job in jobs], threads=threads)
    # Only small summaries travel back; the images are in the EXRs the jobs wrote.
    return [
        {"output": job["output"], "mean": float(r["radiance"].mean()),
         "objects": int(len(set(r["instance_id"].ravel().tolist())))}
        for job, r in zip(jobs, results)
    ]


def turntable(scene_path, count, out, width, height, spp):
    """`count` jobs circling the scene, each writing out/frame_NNNN.exr with IDs."""
    import glint

    # Not through the workers' cache: render_chunk travels to the workers by value, with
    # the globals it uses, and a loaded scene does not pickle.
    scene = glint.load(scene_path)
    lo, hi = scene.bounds
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    radius = max(b - a for a, b in zip(lo, hi))
    jobs = []
    for i in range(count):
        angle = 2 * math.pi * i / count
        position = (centre[0] + 1.6 * radius * math.sin(angle), centre[1] + 0.4 * radius,
                    centre[2] + 1.6 * radius * math.cos(angle))
        jobs.append({
            "width": width, "height": height, "spp": spp, "seed": i,
            "camera": {"position": position, "target": tuple(centre)},
            "aovs": ["instance_id", "material_id", "coverage"],
            "output": str(Path(out) / f"frame_{i:04d}.exr"),
        })
    return jobs


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", help="glTF file (default: the demo scene)")
    parser.add_argument("--jobs", type=int, default=16)
    parser.add_argument("--chunk", type=int, default=4, help="jobs per task")
    parser.add_argument("--out", default="dask-out")
    parser.add_argument("--width", type=int, default=160)
    parser.add_argument("--height", type=int, default=90)
    parser.add_argument("--spp", type=int, default=8)
    parser.add_argument("--scheduler", help="address of a running Dask scheduler")
    parser.add_argument("--workers", type=int, default=2, help="local cluster: worker processes")
    args = parser.parse_args()

    from dask.distributed import Client, LocalCluster

    scene_path = str(Path(args.scene).resolve()) if args.scene else None
    Path(args.out).mkdir(parents=True, exist_ok=True)
    jobs = turntable(scene_path, args.jobs, Path(args.out).resolve(), args.width, args.height,
                     args.spp)
    chunks = [jobs[i:i + args.chunk] for i in range(0, len(jobs), args.chunk)]
    if args.scheduler:
        client = Client(args.scheduler)
        threads = 0  # every core of each worker machine
    else:
        # One thread per worker process in Dask's view; glint's own pool uses the cores.
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True)
        client = Client(cluster)
        threads = 1
    futures = [client.submit(render_chunk, scene_path, chunk, threads, pure=False)
               for chunk in chunks]
    done = [row for chunk in client.gather(futures) for row in chunk]
    for row in done:
        print(f"{row['output']}: mean radiance {row['mean']:.4f}, {row['objects']} IDs")
    print(f"{len(done)} jobs in {len(chunks)} tasks on {len(client.scheduler_info()['workers'])} "
          "workers")
    client.close()


if __name__ == "__main__":
    main()
