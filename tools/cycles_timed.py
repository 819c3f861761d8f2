#!/usr/bin/env python3
# measurement: the CPU time of Cycles' render call, for docs/speed.md. Run: target/tools-venv/bin/python tools/cycles_timed.py SCENE OUT.exr [options]
"""Runs ../shared/peers/cycles_render.py unchanged and measures the CPU time of its render call.

    /work/bpyvenv/bin/python tools/cycles_timed.py SCENE OUT.exr [cycles_render.py's options]

Every argument goes to cycles_render.py as it is; the image and the peer's own JSON line on
stdout are what a direct run gives (same seed, same pixels). After that line this wrapper prints
one more JSON line on stdout:

* `render_cpu_s`: user + sys CPU seconds of the whole process (every thread: Cycles' workers,
  its BVH build, the texture loads) spent inside `bpy.ops.render.render()`, from
  `resource.getrusage(RUSAGE_SELF)` taken just before and just after the call; also
  `render_user_s` and `render_sys_s` apart;
* `render_wall_s`: the wall time of the same interval (the peer's `render_s` times the same call);
* `process_cpu_s`: user + sys of the process when the peer returns (Python start-up,
  `import bpy`, the glTF import, scene setup, the render and the EXR write), for comparison
  with /usr/bin/time's figure.

How the call is found: `bpy.ops.render.render` is an instance of `bpy.ops._BPyOpsSubModOp`
(Blender's scripts/modules/bpy/ops.py), made afresh at every attribute access, so the class's
`__call__` is wrapped, and only calls with module "render" and function "render" are timed. The
class exists once `bpy.ops` is imported, which happens inside the peer's `import bpy`; an import
hook patches it right then, so the peer's own `import_bpy_s` and output are unchanged.
"""

import importlib.abc
import importlib.machinery
import json
import os
import resource
import runpy
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PEER = os.path.normpath(os.path.join(ROOT, "..", "shared", "peers", "cycles_render.py"))

# What the timed render calls measured, in call order (the peer makes exactly one).
RENDER_CALLS = []


def cpu_seconds():
    """(user, sys) CPU seconds of this process, all its threads, terminated ones included."""
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime, r.ru_stime


def time_render_calls(op_class):
    """Wraps op_class.__call__ so that bpy.ops.render.render() records its CPU and wall time."""
    call = op_class.__call__

    def timed_call(self, *args, **kw):
        if (self._module, self._func) != ("render", "render"):
            return call(self, *args, **kw)
        user0, sys0 = cpu_seconds()
        wall0 = time.perf_counter()
        try:
            return call(self, *args, **kw)
        finally:
            wall1 = time.perf_counter()
            user1, sys1 = cpu_seconds()
            RENDER_CALLS.append(dict(render_cpu_s=round((user1 - user0) + (sys1 - sys0), 4),
                                     render_user_s=round(user1 - user0, 4),
                                     render_sys_s=round(sys1 - sys0, 4),
                                     render_wall_s=round(wall1 - wall0, 4)))

    op_class.__call__ = timed_call


class PatchOpsOnImport(importlib.abc.MetaPathFinder):
    """Import hook: when `bpy.ops` is loaded, wrap its operator class before anyone calls it."""

    def find_spec(self, fullname, path, target=None):
        if fullname != "bpy.ops":
            return None
        spec = importlib.machinery.PathFinder.find_spec(fullname, path, target)
        if spec is None or spec.loader is None:
            return None
        exec_module = spec.loader.exec_module

        def exec_and_patch(module):
            exec_module(module)
            time_render_calls(module._BPyOpsSubModOp)

        spec.loader.exec_module = exec_and_patch
        return spec


def main():
    # The peer points fd 1 at stderr so that stdout carries only its JSON line; keep a copy of
    # the real stdout for this wrapper's line.
    sys.stdout.flush()
    json_out = os.fdopen(os.dup(1), "w")
    sys.meta_path.insert(0, PatchOpsOnImport())
    sys.argv = [PEER] + sys.argv[1:]
    runpy.run_path(PEER, run_name="__main__")
    user, sys_ = cpu_seconds()
    if len(RENDER_CALLS) != 1:
        sys.exit(f"cycles_timed: expected one bpy.ops.render.render() call, saw "
                 f"{len(RENDER_CALLS)} (did {PEER} change?)")
    info = dict(RENDER_CALLS[0], process_cpu_s=round(user + sys_, 4), peer=PEER)
    json_out.write(json.dumps(info) + "\n")
    json_out.flush()


if __name__ == "__main__":
    main()
