#!/usr/bin/env python3
"""Places the built-in bottle with dmgplace from Python (the artifacts `scripts/demo` bakes).

usage: PYTHONPATH=<prefix>/lib/python3.11/site-packages examples/python/place.py ARTIFACT_DIR [SECONDS]
"""
import pathlib
import sys

import dmgplace

artifacts = pathlib.Path(sys.argv[1])
seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 5.0
queries = pathlib.Path(__file__).resolve().parents[2] / "datasets" / "queries"
world = dmgplace.World.load(artifacts / "dmgarm.h5", artifacts / "bottle.h5", artifacts / "cabinet.h5")
query = dmgplace.read_query(queries / "cabinet_bottle_blocked.yaml", artifacts)
result = dmgplace.place(world, query, time_limit=seconds,
                        on_solution=lambda s: print(f"  {s['time']:.3f} s: objective {s['objective']:.4f} grasp {s['grasp_state']}"))
if not result["solved"]:
    sys.exit(f"no solution: {result['reason']}")
best = result["best"]
print(f"solved: objective {best['objective']:.6f}, grasp {best['grasp_state']} after {len(best['in_hand'])} in-hand actions, "
      f"arm path of {best['path'].shape[0]} waypoints")
