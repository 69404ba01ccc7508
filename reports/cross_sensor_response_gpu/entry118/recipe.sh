# Sourced by the drivers of research log entries 118-120 (not run alone): the recipe's options for a rescoring
# (`cover_informative` plans, the registry code prior, criterion v, the converged code fit, the plan's residual
# correction, 600 s of ordinary use beside the plan alone), as `--set` arguments in RECIPE. Each driver adds its
# budgets and intervals.
RECIPE=(--set "options.plan_strategies=[cover_informative]"
  --set options.response.code_prior=registry --set options.response.plan_criterion=v
  --set options.response.code_iterations=40 --set options.response.code_tolerance=1e-4
  --set options.response.residual_length=1 --set options.response.residual_ratio=10
  --set "options.response.label_free={with_plans: true, zero_shot: false}")
