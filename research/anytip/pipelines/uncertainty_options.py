"""`options:` of an uncertainty spec: the pipeline and its fault detection read them."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field


class AdaptedOptions(BaseModel):
    """The adapted shared model of `cross_sensor` on held-out units (`options.adapted`)."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)

    kind: str = "input_affine+film"
    epochs: int = Field(4, ge=1, le=10_000, description="shared-model epochs (the spec's recipe otherwise)")
    budget: int = Field(5000, ge=1, le=10_000_000, description="labeled stream rows that fit the adapter")
    calib_rows: int = Field(5000, ge=1, le=10_000_000,
                            description="the next stream rows: the budget's conformal set")
    prior: float = Field(10.0, ge=0, le=1e9)
    calibration_protocol: str | None = "short"
    calibration_interleave: bool = Field(False, description="the protocol's orientations in turn "
                                                           "(cross_sensor's calibration_interleave)")
    scale_epochs: int = Field(10, ge=0, le=10_000,
                              description="scale network epochs; 0 skips the normalised variant")
    members: int = Field(3, ge=1, le=64,
                         description="shared models from different seeds, each calibrated and "
                                              "folded; 2 or more add the `+ensemble` variants")
    test: Literal["patches", "unseen"] = Field(
        "unseen", description="test rows: the held-out patches of cross_sensor, or every row of "
                              "the unit that neither its adapter nor its conformal set saw")
    max_test_rows: int = Field(60000, ge=100, le=10_000_000,
                               description="per unit, a random subset of `unseen` rows")
    hetero: bool = Field(True, description="also a shared model with heteroscedastic heads (beta-NLL "
                                           "with options.beta), adapters fitted the same way: `+hetero`")


class Options(BaseModel):
    """`options:` of an uncertainty spec."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)

    members: int = Field(5, ge=2, le=64, description="deep-ensemble members per unit")
    beta: float = Field(0.5, ge=0, le=1, description="beta-NLL exponent")
    calib_patch_fraction: float = Field(0.2, gt=0, lt=1, description="of the non-test patches")
    max_train_rows: int | None = Field(40000, ge=100, le=10_000_000, description="per unit, random subset")
    nominal: list[Annotated[float, Field(gt=0, lt=1)]] = [0.5, 0.9, 0.95]
    mapie: bool = True
    drift_pa: list[float] = [1000.0, 3000.0]
    foreign_units: int = Field(2, ge=0, le=64, description="simulated units per foreign fleet; 0 skips")
    max_detect_rows: int = Field(40000, ge=100, le=10_000_000, description="rows per unit and fault")
    # rows per detection window: 1 s and 10 s at 200 Hz (flatline and rest offset use the first)
    windows: list[Annotated[int, Field(ge=1, le=1_000_000)]] = Field([200, 2000], min_length=1)
    cv_folds: int = Field(5, ge=0, le=100,
                          description="cross-conformal patch folds per unit; 0 skips (K<2 invalid)")
    bootstrap: int = Field(400, ge=0, le=100_000,
                           description="patch-bootstrap draws per unit and method; 0 skips")
    rest_reference_rows: int = Field(12000, ge=1, le=10_000_000,
                                     description="rows after tare that re-learn the rest state")
    rest_block_rows: int | None = Field(None, ge=2, le=10_000_000,
                                        description="rest-drift block; None: 2x longest press")
    adapted: AdaptedOptions | None = None  # also the adapted shared model (needs >= 3 units)
