"""Research log entry 177: a simulated session of sporadic contacts with rests between them, as a unit in
ordinary use would see, for entry 176's contact detectors.

`USE`: every patch of the three orientations once, in an order spread over the region, one press each at
the next of four force levels (2, 5, 10, 20 N) with a shear cross in two directions, and 3 s at rest before
each press (the protocols' own rests are 1 s before a patch and 0.15 s between its presses): about 170 s
per orientation, from power-up. Simulates N units of the default fleet (seed 177) into a registry:

    python reports/cross_sensor_response_gpu/entry177/simulate_use.py data/use177 16
    python reports/cross_sensor_response_gpu/entry176/contact_from_pressure.py data/use177 SIM use \\
        > reports/cross_sensor_response_gpu/entry177/logs/contact_use.log
"""

from __future__ import annotations

import sys

from anytip.data.registry import Registry
from anytip.data.simulated import simulate_into
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.protocols import Protocol

USE = Protocol(name="use", layers_n=(2.0, 5.0, 10.0, 20.0), layer_cycle=True, directions=2, patch_rest_s=3.0,
               order="spread")

if __name__ == "__main__":
    registry = Registry(sys.argv[1])
    added, unchanged = simulate_into(registry, FleetConfig(), int(sys.argv[2]), seed=177, protocols=(USE,))
    print(f"{added} runs added, {unchanged} already there; {USE.duration_s:.0f} s of robot time per unit")
