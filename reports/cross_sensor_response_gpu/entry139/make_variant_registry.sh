#!/bin/bash
# Research log entry 139: a registry whose plan600 runs are the variant design's (variant.patch applied in a
# worktree, run from there): REG (other16 or fleet88) simulated whole with the variant into a scratch registry,
# and its plan600 runs imported into a copy of data/REGp (data/REGf). Every other run equals data/REGp's.
#   bash .../make_variant_registry.sh other16   (--fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23)
#   bash .../make_variant_registry.sh fleet88   (--units 88 --seed 40)
set -euo pipefail
reg=$1
case $reg in
  other16) args=(--fleet configs/fleets/other_elastomer.yaml --units 16 --seed 23) ;;
  fleet88) args=(--units 88 --seed 40) ;;
esac
scratch=$(mktemp -d)/all
python -c "import sys; from anytip.cli import main; sys.exit(main(sys.argv[1:]))" data simulate \
  --registry "$scratch" "${args[@]}" --protocols full,short,quick,plan120,plan600
rm -rf "data/${reg}f"; cp -a "data/${reg}p" "data/${reg}f"
python - "$scratch" <<'PY' > "$scratch.list"
import sys
from anytip.data.registry import Registry
for r in Registry(sys.argv[1], create=False).list_runs():
    if r.protocol == "plan600":
        print(f"{sys.argv[1]}/{r.path}")
PY
xargs python -c "import sys; from anytip.cli import main; sys.exit(main(['--registry', 'data/${reg}f', 'data', 'import', *sys.argv[1:]]))" < "$scratch.list"
rm -rf "$(dirname "$scratch")"
