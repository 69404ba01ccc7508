"""Mean force / angle RMSE of an arm over validation units of label_free_codes rows."""
import json, sys
import numpy as np
arm, files = sys.argv[1], sys.argv[2:]
rows = [r for f in files for r in json.load(open(f))["rows"] if r["arm"] == arm and r["role"] == "val"]
print(arm, len(rows), "val units:", sorted(r["unit"] for r in rows))
print(f"  force {np.mean([r['force_rmse_n'] for r in rows]):.3f} N, angle {np.mean([r['angle_rmse_rad'] for r in rows]):.4f} rad")
