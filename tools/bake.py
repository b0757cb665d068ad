"""Bake the cloud noise textures into the bake cache and print how long each took.

Bakes the cloud thesis's defaults (shape 128³, detail 32³, weather 512²) and the maritime
thesis's sizes (shape 132³, detail 64³) into ``$NATURA_CACHE`` (default
``~/.cache/natura/bakes``), so the app finds them there. With ``--report`` it also times both
bake paths (compute and fragment) without the cache — ``app.bakes.bake_report``, the numbers
the bench uses.

    python tools/bake.py [--cache DIR] [--force] [--report] [--json FILE] [--prune N]
"""

from __future__ import annotations

import argparse
import json
import sys


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cache",
                    help="cache directory (default: $NATURA_CACHE or ~/.cache/natura/bakes)")
    ap.add_argument("--force", action="store_true",
                    help="rebake even when a valid cache file exists")
    ap.add_argument("--path", choices=("auto", "compute", "fragment"), default="auto",
                    help="bake path for the cache fill (auto: compute where GL >= 4.3)")
    ap.add_argument("--report", action="store_true", help="also time both paths without the cache")
    ap.add_argument("--json",
                    help="write the report rows (and the cache fill) as JSON to this file")
    ap.add_argument("--prune", type=int, default=None, metavar="N",
                    help="afterwards keep only the N newest files per kind and size")
    args = ap.parse_args(argv)

    from app.bakes import BakeCache, bake, bake_report, defaults, key_for, maritime
    from app.gpu.device import Gpu

    gpu = Gpu()
    cache = BakeCache(args.cache) if args.cache else BakeCache()
    use_compute = None if args.path == "auto" else args.path == "compute"
    print(f"device: {gpu.caps.describe()}; cache: {cache.directory}")
    filled = []
    try:
        for spec in defaults() + maritime():
            if args.force:
                file = cache.path_for(spec.kind, spec.size, key_for(spec, gpu.shaders))
                file.unlink(missing_ok=True)

            def progress(f, spec=spec):
                print(f"\r  {spec.kind} {spec.size}: {100 * f:5.1f} %", end="", file=sys.stderr,
                      flush=True)

            result = bake(gpu, spec, cache=cache, use_compute=use_compute, progress=progress)
            print("\r", end="", file=sys.stderr)
            print(" ", result.summary())
            filled.append({"kind": spec.kind, "size": spec.size, "cache": result.cache,
                           "path": result.path, "bake_seconds": result.bake_seconds,
                           "seconds": result.seconds,
                           "file": str(result.cache_file) if result.cache_file else None})
        rows = []
        if args.report:
            print("uncached bake times (programs compiled beforehand):")
            rows = bake_report(gpu)
            for r in rows:
                print(f"  {r['kind']:8s} {r['size']:4d}  {r['path']:9s} {r['seconds']:8.3f} s  "
                      f"{r['texels_per_s'] / 1e6:7.2f} Mtexel/s  {r['mib']:5.2f} MiB")
        if args.prune is not None:
            for f in cache.prune(args.prune):
                print(f"  pruned {f.name}")
        if args.json:
            with open(args.json, "w", encoding="utf-8") as fh:
                json.dump({"device": gpu.caps.describe(), "cache_fill": filled, "report": rows},
                          fh, indent=2)
    finally:
        gpu.release()
    return 0


if __name__ == "__main__":
    sys.exit(main())
