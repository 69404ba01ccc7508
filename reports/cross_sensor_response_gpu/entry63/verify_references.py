"""Research log entry 63, rule 1: the fold's (argv[1]) saved other16 references (folds16 models) scored
again on the run's own test rows must equal its per_unit rows. From the repository root, research/ on
PYTHONPATH."""

import importlib.util
import sys
from pathlib import Path

import torch

from anytip.config import load_spec
from anytip.data.registry import Registry
from anytip.pipelines.common import Context, load
from anytip.pipelines.cross_sensor import min_units, prepare
from anytip.pipelines.cross_sensor_options import parse_options
from anytip.rundir import read_json

found = importlib.util.spec_from_file_location("rescore", "scripts/rescore_response.py")
rescore = importlib.util.module_from_spec(found)
found.loader.exec_module(rescore)
k = int(sys.argv[1])
run = Path(f"reports/cross_sensor_response_start/other16_seed{k}")
spec = load_spec(run / "config.yaml", ["options.adapters=[]", "options.extra_units=null"])
registry = Registry(Path("data/other16"), create=False)
ctx = Context(spec, registry, Path("/tmp/vr"), torch.device("cpu"), False, {})
opts = parse_options(ctx)
arrays = load(ctx, min_units(ctx))
sd = prepare(ctx, arrays, opts, k, None)
rows = [r for r in read_json(run / "metrics.json")["results"] if r["method"] == "per_unit"]
models = Path(f"reports/cross_sensor_response_folds16/seed{k}/models")
again = rescore._scored_again(rows, models, arrays, sd, opts, k)
pairs = zip(rows, again, strict=True)
bad = [(a["unit"], {x: (a[x], b[x]) for x in a if a[x] != b[x]}) for a, b in pairs if a != b]
print(f"fold {k}: {len(rows)} rows, {len(bad)} differ", bad)
