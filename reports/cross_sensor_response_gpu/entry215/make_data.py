"""Research log entry 215: entry 191's 64 fresh validation units with their designed 120 s plan of random
points. `data/val215d` and `data/val215o`: linked copies of `data/fleet88p` and `data/other16p`, as entry 191
made `data/val191d` and `data/val191o`, with the same 32 units each (seeds 41 and 24) pressed through the full
protocol and the designed 120 s plan at its default 2 s moves, its cells and loads drawn at random
(`design_protocol(120, points="random")`, what `anytip data simulate --plan-points random` runs). The gate
(rule 1): every fresh unit's full runs hash as its runs in entry 191's registries, and its plan takes the
Halton plan's robot time. Entry 216 (`cells`): `data/val216d` and `data/val216o`, the plan's cells drawn at
random with its loads in turn (order `random`, `layers_random` off).

    python reports/cross_sensor_response_gpu/entry215/make_data.py > \\
        reports/cross_sensor_response_gpu/entry215/logs/data.log
    python reports/cross_sensor_response_gpu/entry215/make_data.py cells > \\
        reports/cross_sensor_response_gpu/entry215/logs/data216.log
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

from anytip.data.registry import Registry
from anytip.data.simulated import simulate_into
from anytip.sensor.fleet import FleetConfig, load_fleet_config
from anytip.sensor.protocols import design_protocol

HERE = Path(__file__).parent
linked_copy = runpy.run_path(str(HERE.parent / "entry178" / "make_registries.py"))["linked_copy"]
UNITS = 32
# (source registry, entry 191's registry, target, fleet config or None for the default fingertip, seed)
REGISTRIES = (("data/fleet88p", "data/val191d", "data/val215d", None, 41),
              ("data/other16p", "data/val191o", "data/val215o", "configs/fleets/other_elastomer.yaml", 24))


def hashes(registry: Registry, prefix: str) -> dict[tuple[str, str], str]:
    """{(run id, protocol): content hash} of `registry`'s runs of units whose id starts with `prefix`."""
    return {(r.run_id, r.protocol): registry.open_run(r.run_id).content_hash()
            for r in registry.list_runs() if r.unit.startswith(prefix)}


def main(arm: str = "random") -> None:
    """Entry 215's registries (`arm` 'random': cells and loads drawn at random) or entry 216's ('cells')."""
    halton = design_protocol(120.0)
    plan = (design_protocol(120.0, points="random") if arm == "random"
            else halton.model_copy(update={"order": "random"}))
    assert plan.duration_s == halton.duration_s
    for source, before, target, fleet, seed in REGISTRIES:
        target = target if arm == "random" else target.replace("215", "216")
        reg = linked_copy(Path(source), Path(target))
        config = FleetConfig() if fleet is None else load_fleet_config(fleet)
        added, _ = simulate_into(reg, config, UNITS, seed=seed, protocols=("full", plan))
        prefix = f"SIM{seed}-"
        new, old = hashes(reg, prefix), hashes(Registry(before), prefix)
        full_same = sum(new[k] == old.get(k) for k in new if k[1] == "full")
        plans_differ = sum(new[k] != old.get(k) for k in new if k[1] == "plan120")
        print(f"{target}: {added} runs of {UNITS} units (seed {seed}) added to a copy of {source}; "
              f"rule 1: {full_same} of {sum(k[1] == 'full' for k in new)} full runs hash as in {before}, "
              f"{plans_differ} of {sum(k[1] == 'plan120' for k in new)} plan runs differ from its Halton "
              f"plans")


if __name__ == "__main__":
    main(*sys.argv[1:])
