"""`scripts/rescore_response.py` with the pooled start network drawn again (research log entry 83):
its seed is the run's seed plus 1000 x DRAW, and it trains EPOCHS epochs (the recipe's
`inverse_epochs` for the units' networks is left as it is). Draw 0 at the recipe's epochs is the
run itself. Prints the start network's best loss on its own validation rows. Usage, from the
repository root:

    python reports/cross_sensor_response_gpu/entry83/start_draw.py DRAW EPOCHS RUN \\
        --registry REG --out OUT [rescore_response.py's options]
"""

import os
import runpy
import sys
from dataclasses import replace

import anytip.pipelines.cross_sensor_response as pipe

if len(sys.argv) < 4 or not (sys.argv[1].isdigit() and sys.argv[2].isdigit()):
    sys.exit(__doc__)
DRAW, EPOCHS = int(sys.argv.pop(1)), int(sys.argv.pop(1))
trained = pipe.start_network


def drawn(source, shape, recipe, seed, *rest, **kwargs):
    """The start network of draw DRAW, trained EPOCHS epochs."""
    fit = trained(source, shape, replace(recipe, inverse_epochs=EPOCHS), seed + 1000 * DRAW, *rest, **kwargs)
    best = min(r["val_loss"] for r in fit.unit_history(0))
    print(f"start network: draw {DRAW}, seed {seed + 1000 * DRAW}, {EPOCHS} epochs, best val_loss {best:.6g}",
          flush=True)
    return fit


pipe.start_network = drawn
# another wrapper of rescore_response.py may run in its place (RESCORE_SCRIPT; research log entry 95)
script = os.environ.get("RESCORE_SCRIPT", "scripts/rescore_response.py")
sys.argv[0] = script
runpy.run_path(script, run_name="__main__")
