"""`options:` of a cross_sensor spec: budgets (samples or robot seconds) and plans, adapters and
their priors, the per-unit reference, and how they are checked before any work."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from anytip.config import DataConfig
from anytip.data.plans import INFORMED, Budget, BudgetUnit, Criterion, RigTiming, Strategy
from anytip.errors import AnytipError
from anytip.models.adapted import parse_kind
from anytip.models.mlp import MLPConfig
from anytip.models.response import ResponseConfig
from anytip.pipelines.common import Context, validate_options
from anytip.train.adapt import ADAPTER_DECAY, AdapterRecipe
from anytip.train.adapter_prior import PriorFamily
from anytip.train.episodic import EpisodeRecipe
from anytip.train.label_free import LabelFreeRecipe
from anytip.train.recipe import TrainRecipe
from anytip.train.response import ResponseRecipe

SCRATCH = TrainRecipe(name="scratch", optimizer="adamw", lr=3e-3, weight_decay=1e-4, batch_size=256,
                      epochs=100, schedule="cosine", final_lr_frac=0.01, keep_best=False)


class RigOptions(BaseModel):
    """`options.rig`: rig time besides contact, and the labels' decorrelation rate."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    move_s: float = Field(default=RigTiming.move_s, ge=0, le=3600)
    remount_s: float = Field(default=RigTiming.remount_s, ge=0, le=36_000)
    effective_hz: float = Field(default=RigTiming.effective_hz, gt=0, le=100_000)

    def timing(self) -> RigTiming:
        return RigTiming(self.move_s, self.remount_s, self.effective_hz)


class FitVariant(BaseModel):
    """One way of fitting a new unit's adapter on a shared model: `add` parts to the shared
    model's adapter kind at calibration (e.g. `lowrank4`: a foldable low-rank change of every
    layer, fitted on the unit alone), with `steps` Adam steps (default `adapter_steps`); or
    `inner`: the inner fit an episodic shared model learnt (`episodic.inner_steps` full-batch
    steps with its learnt step sizes, no prior; episodic shared models only)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    add: str = ""
    steps: int | None = Field(default=None, ge=1, le=1_000_000)
    inner: bool = False

    @model_validator(mode="after")
    def _inner_alone(self) -> FitVariant:
        if self.inner and (self.add or self.steps is not None):
            raise ValueError("an inner fit takes the episodic model's own kind and steps: no add, no steps")
        return self

    def kind(self, shared_kind: str) -> str:
        """The adapter kind fitted on a shared model of `shared_kind`."""
        if not self.add:
            return shared_kind
        return self.add if shared_kind == "none" else f"{shared_kind}+{self.add}"

    def suffix(self) -> str:
        """What a method name says of the fit besides its kind: its steps where set."""
        if self.inner:
            return "[inner fit]"
        return "" if self.steps is None else f"[{self.steps} steps]"

    def recipe(self, opts: Options, inner_lr: dict[str, float] | None) -> AdapterRecipe:
        """How this fit fits a new unit's adapter: Adam (`steps` or `adapter_steps`), or the inner
        fit with a shared model's learnt step sizes `inner_lr`."""
        if not self.inner:
            return AdapterRecipe(self.steps or opts.adapter_steps, opts.adapter_lr)
        if inner_lr is None:
            raise AnytipError("an inner fit needs a shared model trained episodically")
        return AdapterRecipe(opts.episodic.inner_steps, opts.adapter_lr, rates=dict(inner_lr))


class ExtraUnits(BaseModel):
    """`options.extra_units`: more training units for the shared models, from another registry
    of the same sensor model (for example hundreds of simulated units with wide variation).
    They train every shared model beside the registry's training units, with their own
    adapters; they are never validation or held-out units, and no unit may be in both
    registries."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    registry: str = Field(min_length=1, description="the other registry's directory")
    protocol: str | list[str] | None = None  # which of its runs (None: all)
    max_units: int | None = Field(default=None, ge=1, le=100_000)  # chosen by the spec's seed

    def data(self) -> DataConfig:
        return DataConfig(protocol=self.protocol, max_units=self.max_units)


class EpisodicOptions(BaseModel):
    """`options.episodic`: how episodic shared training draws and fits its episodes
    (train/episodic.py); used by the shared models whose `shared_training` is `episodic`."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    presses: int = Field(default=EpisodeRecipe.presses, ge=1, le=10_000)
    rows_per_press: int = Field(default=EpisodeRecipe.rows_per_press, ge=1, le=100_000)
    inner_steps: int = Field(default=EpisodeRecipe.inner_steps, ge=1, le=1000)
    inner_lr: float = Field(default=EpisodeRecipe.inner_lr, gt=0, le=100)
    weight: float = Field(default=EpisodeRecipe.weight, gt=0, le=1e6)
    units_per_step: int | None = Field(default=None, ge=1, le=1_000_000)

    def recipe(self) -> EpisodeRecipe:
        return EpisodeRecipe(**self.model_dump())


class IntervalOptions(BaseModel):
    """`options.intervals`: prediction intervals of each calibrated held-out unit from its own
    plan (split conformal on out-of-fold residuals: the plan's presses dealt into `folds`
    folds, each predicted by the adapter refitted without it), scored on its test patches."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    folds: int = Field(default=5, ge=2, le=100)
    level: float = Field(default=0.9, gt=0, lt=1, description="nominal coverage")
    transfer_check: bool = Field(
        default=False, description="response transfer: also train each unit a network on its transferred "
        "rows alone, whose residuals on the plan's rows (which it never saw) give a second interval "
        "(`transfer_` fields) beside the plan's own residuals (research log entry 28)")
    factor_units: int = Field(
        default=0, ge=0, le=100_000, description="response transfer: units dealt after the training units "
        "(neither trained on nor held out; needs splits.n_train_units) calibrated as validation units are, "
        "that learn the intervals' fleet factor with the validation units and choose nothing else "
        "(research log entry 50)")


class LabelFreeOptions(BaseModel):
    """`options.response.label_free`: a zero-shot row `response:label_free` (train/label_free.py). A
    new unit's codes come from its pressures in `seconds` of ordinary use after mounting (whole presses
    drawn at random from its stream, `anytip.data.plans.ordinary_use`; no labels, no rig time), by the
    joint fit of codes and contacts from a searched start (from the codes a fleet encoder predicts
    from the unit's pressure statistics), both held to the fleet's force scale; its network trains on
    the training units' rows carried over by those codes alone. Needs `inverse_start: pooled` (the
    pull's contacts)."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    seconds: float = Field(default=LabelFreeRecipe.seconds, gt=0, le=600,
                           description="contact seconds of ordinary use read (the issue allows 600)")
    rows: int = Field(default=LabelFreeRecipe.rows, ge=1, le=2**20)
    pull: float = Field(default=LabelFreeRecipe.pull, gt=0, le=1e6)
    candidates: int = Field(default=LabelFreeRecipe.candidates, ge=1, le=2**22)
    rounds: int = Field(default=LabelFreeRecipe.rounds, ge=0, le=1000)
    iterations: int = Field(default=LabelFreeRecipe.iterations, ge=1, le=100_000)
    force_scale: bool = Field(
        default=LabelFreeRecipe.force_scale, description="hold the search and the fit to the force scale of "
        "the training units' own ordinary use (research log entry 40)")
    start: Literal["encoder", "zero"] = Field(
        default=LabelFreeRecipe.start, description="the search's first codes: predicted from the unit's "
        "pressure statistics by an encoder learnt across the response model's units whose streams the run "
        "holds (zero where it explains nothing of left-out units' codes), or zero (research log entry 44)")
    plan_rows: int | None = Field(
        default=LabelFreeRecipe.plan_rows, ge=1, le=2**22, description="at most this many of a plan's "
        "labeled rows, evenly spaced, enter its joint fit with the ordinary use (null: all of them; "
        "research log entry 46)")
    distil: Literal["none", "fitted", "oracle"] = Field(
        default=LabelFreeRecipe.distil, description="with_plans: the ordinary use's fitted rows also train "
        "the unit's network, labeled with the joint fit's contacts (`fitted`, rows `response+use+distil@`), "
        "with their true contacts (`oracle`, a research ceiling that `anytip calibrate` refuses, rows "
        "`response+use+oracle@`), or not (`none`, the default; research log entry 78)")
    distil_repeat: int = Field(default=LabelFreeRecipe.distil_repeat, ge=1, le=1000,
                               description="times each of those rows enters the unit's network's rows")
    plan_iterations: int | None = Field(
        default=LabelFreeRecipe.plan_iterations, ge=1, le=100_000, description="steps of the joint fit "
        "with a plan's labeled rows (null: `iterations`; research log entry 81: 10 give the validation "
        "units' error of 30 in a third of the time)")
    use_weight: float = Field(
        default=LabelFreeRecipe.use_weight, gt=0, le=1e6, description="with_plans: in the joint fit with a "
        "plan's labeled rows, the unlabeled rows weigh this times their independent rows (research log "
        "entry 187: the fit follows the ratio of the two weights)")
    search_draw: int = Field(
        default=LabelFreeRecipe.search_draw, ge=0, le=1_000_000, description="which random draw of the "
        "training units' labeled contacts the search reads (0: the one every run before research log "
        "entry 219 read)")
    starts: int = Field(
        default=LabelFreeRecipe.starts, ge=1, le=64, description="the label-free fit runs from this many "
        "draws of contacts in turn (`search_draw` on) and a unit takes the mean of their codes (research "
        "log entry 220)")
    final_scale: bool = Field(
        default=LabelFreeRecipe.final_scale, description="after the label-free fit, scale its contacts' "
        "forces to the force-scale prior's mean square and refit the codes to them (research log entry 223: "
        "x0.967 in force on fleet88's validation units)")
    with_plans: bool = Field(
        default=False, description="also calibrate every labeled budget with the unit's ordinary use: its "
        "codes from one joint fit of the plan's labeled rows and the ordinary use's unlabeled ones, rows "
        "`response+use@<strategy>` beside `response@<strategy>` (research log entry 45)")

    zero_shot: bool = Field(
        default=True, description="the zero-shot row `response:label_free`; false (with with_plans) scores "
        "only the labeled budgets with ordinary use, without the label-free search's cost")

    @model_validator(mode="after")
    def _something_to_score(self) -> LabelFreeOptions:
        if not self.zero_shot and not self.with_plans:
            raise ValueError("zero_shot: false leaves nothing to score without with_plans: true")
        return self

    def recipe(self) -> LabelFreeRecipe:
        return LabelFreeRecipe(**self.model_dump(exclude={"with_plans", "zero_shot"}))


class ResponseOptions(BaseModel):
    """`options.response`: calibration by response transfer (train/response.py), a method `response`
    beside the adapters at every labeled budget. A fleet response model (contact -> each barometer's
    pressure, a code per unit and barometer) is trained on the training units; a new unit's codes are
    fitted on its plan; the training units' rows, carried over to the new unit, train its own network
    of the spec's `model` shape with its plan's rows."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    code_dim: int = Field(default=ResponseConfig.code_dim, ge=1, le=1024)
    channel_dim: int = Field(default=ResponseConfig.channel_dim, ge=1, le=1024)
    hidden: int = Field(default=ResponseConfig.hidden, ge=1, le=4096)
    layers: int = Field(default=ResponseConfig.layers, ge=1, le=16)
    steps: int = Field(default=ResponseRecipe.steps, ge=1, le=10_000_000)
    rows_per_step: int = Field(default=ResponseRecipe.rows_per_step, ge=1, le=2**22)
    lr: float = Field(default=ResponseRecipe.lr, gt=0, le=10)
    code_decay: float = Field(default=ResponseRecipe.code_decay, ge=0, le=1e6)
    code_fit: Literal["gauss_newton", "adam"] = Field(
        default=ResponseRecipe.code_fit,
        description="how a new unit's codes are fitted (train/response.py fit_codes)")
    code_prior: Literal["diagonal", "barometer", "registry"] = Field(
        default=ResponseRecipe.code_prior,
        description="the prior a new unit's codes are fitted under (train/code_prior.py)")
    plan_criterion: Criterion = Field(
        default=ResponseRecipe.plan_criterion,
        description="what `informative` and `cover_informative` plans maximise: v, minus the pressure "
        "variance the codes leave; d, the log det of each barometer's code precision (data/plans.py "
        "CodeInformation; research log entries 90-91)")
    code_draw_scale: float = Field(
        default=ResponseRecipe.code_draw_scale, ge=0, le=1e6,
        description="where a unit's codes are fitted on its plan alone, each transferred row's codes are "
        "drawn from their Laplace posterior with its covariance times this (0: the MAP codes; research "
        "log entry 94)")
    code_iterations: int = Field(default=ResponseRecipe.code_iterations, ge=1, le=10_000)
    code_tolerance: float = Field(
        default=ResponseRecipe.code_tolerance, ge=0, lt=1,
        description="a barometer's Gauss-Newton code fit stops once a step moves its loss by less than "
        "this share of it (0: every one of code_iterations steps; research log entry 99)")
    code_steps: int = Field(default=ResponseRecipe.code_steps, ge=1, le=1_000_000)
    code_rows: int = Field(default=ResponseRecipe.code_rows, ge=1, le=2**22)
    code_lr: float = Field(default=ResponseRecipe.code_lr, gt=0, le=10)
    residual_length: float = Field(
        default=ResponseRecipe.residual_length, ge=0, le=1e6,
        description="> 0: each transferred row also carries the new unit's misfit at its contact, a Gaussian "
        "process through its plan's residuals with this kernel length in standard deviations of the "
        "contact (train/response.py plan_correction; 0: none; research log entry 101)")
    residual_ratio: float = Field(
        default=ResponseRecipe.residual_ratio, gt=0, le=1e9,
        description="that process's noise variance over its kernel's (larger: a smoother, smaller "
        "correction)")
    residual_rows: int = Field(default=ResponseRecipe.residual_rows, ge=1, le=4096,
                               description="plan rows, evenly spaced, that process is fitted on")
    residual_level: Literal["kept", "centred"] = Field(
        default=ResponseRecipe.residual_level,
        description="where a unit's codes come from its plan and its ordinary use together, that process "
        "learns the plan's residuals as they are (kept) or less each barometer's mean (centred: the plan "
        "session's own offset reaches no transferred row; research log entries 130-131)")
    source_rows: int = Field(default=ResponseRecipe.source_rows, ge=1, le=10_000_000)
    transfer_from: Literal["all", "registry"] = Field(
        default=ResponseRecipe.transfer_from,
        description="whose rows a new unit's network trains on: every unit that trained the response "
                    "model (`extra_units` included), or the registry's own training units")
    inverse_epochs: int = Field(default=ResponseRecipe.inverse_epochs, ge=1, le=100_000)
    inverse_batch: int = Field(default=ResponseRecipe.inverse_batch, ge=1, le=2**20)
    inverse_lr: float = Field(default=ResponseRecipe.inverse_lr, gt=0, le=10)
    inverse_start: Literal["scratch", "pooled"] = Field(
        default=ResponseRecipe.inverse_start,
        description="where a new unit's network starts: random weights, or one network trained on the "
                    "source rows as measured (train/response.py start_network)")

    label_free: LabelFreeOptions | None = Field(
        default=None, description="a zero-shot row from unlabeled ordinary use (train/label_free.py)")
    plan_strategy: Strategy | None = Field(
        default=None,
        description="the press selection decided beforehand for response transfer's calibrations, on more "
        "validation units than a run holds (research log entries 98, 100): one of `plan_strategies`. The "
        "response model records it, `anytip calibrate` takes it and the report names it beside the run's "
        "own choice. null: the run's validation units choose (calibrate.response_strategy)")

    @model_validator(mode="after")
    def _label_free_needs_a_start(self) -> ResponseOptions:
        if self.label_free is not None and self.inverse_start != "pooled":
            raise ValueError("label_free needs inverse_start: pooled (its fit pulls each unlabeled row "
                             "towards the pooled start network's contact)")
        return self

    def config(self) -> ResponseConfig:
        return ResponseConfig(self.code_dim, self.channel_dim, self.hidden, self.layers)

    def recipe(self) -> ResponseRecipe:
        return ResponseRecipe(**self.model_dump(exclude={"code_dim", "channel_dim", "hidden", "layers",
                                                         "label_free", "plan_strategy"}))


Training = Literal["joint", "episodic"]


class Options(BaseModel):
    """`options:` of a cross_sensor spec."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    budgets: list[Annotated[float, Field(ge=0, le=10_000_000)]] = Field(
        default=[0, 50, 200, 1000, 5000], min_length=1,
        description="labeled samples (budget_unit samples) or robot seconds (budget_unit seconds)")
    budget_unit: BudgetUnit = Field(
        default="samples", description="samples: the first rows of the calibration stream; seconds: "
                                       "whole presses up to that robot time (data/plans.py)")
    plan_strategies: list[Strategy] = Field(
        default=["spread"], min_length=1, description="press selections compared (budget_unit seconds)")
    designed_scale: float = Field(
        default=1.0, ge=1.0, le=10.0,
        description="strategy designed at a budget of B robot seconds takes the unit's runs of the design "
        "of B * designed_scale seconds (plan<seconds>), in recorded order up to B: its presses in the unit's "
        "test patches are left out, so 1 / (1 - splits.patch_test_fraction) fills B as a lab's B seconds "
        "would (research log entry 146); 1: the design of B itself")
    rig: RigOptions = RigOptions()
    adapter_priors: list[PriorFamily] = Field(
        default=["identity"], min_length=1,
        description="identity: new adapters start at and are pulled to the identity; empirical: to a "
        "Gaussian learnt from the training units' adapters (train/adapter_prior.py). Each is a method "
        "(suffix /empirical); the first is what anytip calibrate uses")
    prior_rank: int = Field(default=4, ge=0, le=1000)
    reference: TrainRecipe | None = Field(
        default=None, description="the per-unit reference's recipe (default: the spec's training)")
    reference_lrs: list[Annotated[float, Field(gt=0, le=10)]] = Field(
        default=[], description="learning rates tried for the reference, each unit keeping the one with "
        "the lowest loss on its own validation rows (empty: the recipe's own)")
    reference_starts: int = Field(
        default=1, ge=1, le=16, description="starts of the reference's network tried with each learning "
        "rate, each unit keeping the fit with the lowest loss on its own validation rows (research log "
        "entry 164)")
    reference_val: Literal["rows", "patches"] = Field(
        default="rows", description="the reference's validation: random rows, or whole patches of its "
        "calibration (early stopping and the learning-rate choice then judge unseen patches)")
    adapters: list[str] = ["input_diag", "input_affine+film", "input_affine+embedding+film"]
    priors: list[Annotated[float, Field(ge=0, le=1e9)]] = Field(
        default=[1.0, 10.0, 100.0, 1000.0], min_length=1)
    calibration_protocol: str | None = "short"
    calibration_interleave: bool = Field(
        default=False, description="the calibration protocol's runs (orientations) take turns, "
                                   "patch visit by patch visit, instead of following each other")
    fits: list[FitVariant] = Field(
        default=[FitVariant()], min_length=1,
        description="ways a new unit's adapter is fitted on each shared model, each a method; the "
        "first is what anytip calibrate uses. The empirical prior applies to fits without `add` only")
    adapter_steps: int = Field(default=AdapterRecipe.steps, ge=1, le=1_000_000)
    adapter_lr: float = Field(default=AdapterRecipe.lr, gt=0, le=10)
    # pulls training units' adapters to identity
    adapter_decay: float = Field(default=ADAPTER_DECAY, ge=0, le=1e9)
    # the chance a training unit's adapter is left out of a step of shared training
    adapter_dropout: float = Field(default=0.0, ge=0, lt=1)
    shared_training: list[Training] = Field(
        default=["joint"], min_length=1,
        description="how each shared model with adapters is trained, each a method: joint (every "
        "training unit's adapter fitted with the shared weights) or episodic (also adapters fitted on "
        "a few presses and scored on the unit's other rows; method suffix ~episodic)")
    episodic: EpisodicOptions = EpisodicOptions()
    intervals: IntervalOptions | None = Field(
        default=None, description="intervals from each held-out unit's own plan, for the first fit of "
        "every shared model at the chosen prior (budget_unit seconds)")
    extra_units: ExtraUnits | None = None
    response: ResponseOptions | None = Field(
        default=None, description="calibration by response transfer, a method `response` at every labeled "
        "budget (train/response.py); null: not run")
    reference_shapes: list[MLPConfig] = Field(
        default=[], description="more per-unit models of other shapes (model blocks), each trained and "
        "selected exactly like the reference: a method `per_unit:<sizes>` with its ratio to the reference")
    shared_model: MLPConfig | None = Field(
        default=None, description="the shape of the shared (and pooled) models, as a model block: "
        "`{hidden: [32, 128, 128]}`; adapters fold into it. The per-unit reference and the budget-only "
        "MLP keep the spec's `model` (default: the spec's model for all)")
    scratch: TrainRecipe = SCRATCH
    unlabeled_s: float | None = Field(
        default=None, ge=0, le=1e7, description="seconds of a new unit's stream whose pressures (no "
        "labels) set its input statistics: ordinary use after mounting, free of rig time (default all)")
    scratch_budgets: list[Annotated[float, Field(ge=0, le=10_000_000)]] | None = Field(
        default=None, description="the budgets the budget-only MLP is trained at (default: all)")
    train_unit_counts: list[Annotated[int, Field(ge=1, le=100_000)]] = [4, 8, 16]
    sweep_adapter: str = "input_affine+film"
    sweep_budget: float = Field(default=1000, ge=0, le=10_000_000)
    sweep_seeds: int = Field(default=1, ge=0, le=1000)  # the first k seeds also run the unit-count sweep

    def shared_shape(self, model: MLPConfig, source: str, sensor_model: str) -> MLPConfig:
        """The shared models' shape, given the spec's `model` already fitted to the sensor model's
        channels and targets: `shared_model` with the same ends, or `model` itself."""
        if self.shared_model is None:
            return model
        return _with_ends(self.shared_model, model, f"{source}: options.shared_model", sensor_model)

    def reference_shapes_for(self, model: MLPConfig, source: str, sensor_model: str) -> list[MLPConfig]:
        """`reference_shapes` with the ends of the spec's `model` (fitted to the sensor model)."""
        return [_with_ends(shape, model, f"{source}: options.reference_shapes[{k}]", sensor_model)
                for k, shape in enumerate(self.reference_shapes)]


def _with_ends(shape: MLPConfig, model: MLPConfig, where: str, sensor_model: str) -> MLPConfig:
    """`shape` with the input and output widths of `model` (the spec's, fitted to the sensor);
    explicit sizes that disagree are refused naming `where`."""
    return shape.for_sensor(model.sizes[0], model.sizes[-1], where, sensor_model)


def parse_options(ctx: Context) -> Options:
    raw = dict(ctx.spec.options)
    if isinstance(raw.get("scratch"), dict):  # a partial recipe overrides the default's keys
        raw["scratch"] = {**SCRATCH.model_dump(), **raw["scratch"]}
    if isinstance(raw.get("reference"), dict):  # likewise over the spec's training recipe
        raw["reference"] = {**ctx.spec.training.model_dump(), **raw["reference"]}
    opts = validate_options(ctx, Options, raw)
    for kind in [*opts.adapters, opts.sweep_adapter]:
        for fit in opts.fits:
            parse_kind(fit.kind(kind))
    if opts.intervals is not None and opts.budget_unit != "seconds":
        raise AnytipError("options.intervals: intervals are cross-fitted over a plan's presses; they "
                          "need budget_unit seconds")
    if opts.budget_unit == "samples" and any(b != int(b) for b in opts.budgets):
        raise AnytipError(f"options.budgets: with budget_unit samples, budgets are whole sample counts, "
                          f"got {opts.budgets}")
    decided = opts.response.plan_strategy if opts.response is not None else None
    if decided is not None and (opts.budget_unit != "seconds" or decided not in opts.plan_strategies
                                or decided == "designed"):
        raise AnytipError(f"options.response.plan_strategy: {decided!r} is not a press selection this spec "
                          f"compares (budget_unit seconds; options.plan_strategies {opts.plan_strategies}, "
                          "`designed` excluded: a designed plan is a run of its own)")
    return opts


def training_tag(training: Training) -> str:
    """What a method name says of its shared model's training: nothing for joint."""
    return "" if training == "joint" else f"~{training}"


def budget_list(opts: Options, amounts: list[float] | None = None, response: bool = False) -> list[Budget]:
    """The spec's budgets (or `amounts`): one per amount, or in seconds one per amount and press
    selection strategy (the label-free budget 0 once). `informative` and `cover_informative` plans
    choose presses with a response model, so only the response method (`response`) gets them."""
    amounts = opts.budgets if amounts is None else amounts
    if opts.budget_unit == "samples":
        return [Budget(int(b)) for b in amounts]
    labeled = plan_strategies(opts, response)
    return [Budget(float(b), "seconds", s) for b in amounts
            for s in (labeled if b > 0 else opts.plan_strategies[:1])]


def plan_strategies(opts: Options, response: bool = False) -> list[Strategy]:
    """The spec's press selections a method compares: all of them for the response method
    (`response`), all but those chosen with its model (`informative`, `cover_informative`) for the others."""
    return [s for s in opts.plan_strategies if response or s not in INFORMED]
