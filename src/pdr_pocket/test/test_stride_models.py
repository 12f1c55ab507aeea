"""The stride models' registry (pdr_pocket.step_length.STRIDE_MODELS): every name builds
from the configuration, an unknown one is refused naming the known ones, and a model
added to the registry is a valid ``step_length.model`` with no other change."""
from __future__ import annotations

import math
from dataclasses import replace

import pytest

from pdr_pocket.config import StepLengthConfig
from pdr_pocket.placement import MODEL_AT
from pdr_pocket.step_length import AUTO_MODEL, STRIDE_MODELS, Scaled, StrideInputs, stride_model

WALKING_STRIDE = StrideInputs(amplitude_deg=40.0, duration_s=1.1, vertical_range_mps2=8.0)


@pytest.mark.parametrize("name", list(STRIDE_MODELS))
def test_every_registered_model_builds_from_the_configuration(name):
    config = StepLengthConfig(model=name)
    model = stride_model(config)
    assert type(model) is STRIDE_MODELS[name]
    length = model.length(WALKING_STRIDE)
    assert math.isfinite(length) and 0.5 < length < 2.5
    # uncalibrated, scaled by the person's height
    scaled = stride_model(config, height_m=1.87)
    assert isinstance(scaled, Scaled)
    assert scaled.length(WALKING_STRIDE) == pytest.approx(1.1 * length)


def test_the_thesis_models_are_registered_and_auto_chooses_among_them():
    assert {"pitch", "frequency", "weinberg"} <= set(STRIDE_MODELS)
    assert StepLengthConfig().model == AUTO_MODEL
    assert set(MODEL_AT.values()) <= set(STRIDE_MODELS)


def test_an_unknown_model_is_refused_naming_the_known_ones():
    with pytest.raises(ValueError, match="'stride_of_the_art'") as refused:
        StepLengthConfig(model="stride_of_the_art")
    for name in STRIDE_MODELS:
        assert name in str(refused.value)


class Constant:
    """A model that is no more than its registry entry: one stride for every cycle."""

    def __init__(self, stride_m: float) -> None:
        self.stride_m = stride_m

    @classmethod
    def from_config(cls, config: StepLengthConfig) -> Constant:
        return cls(config.stairs_stride_m)

    def length(self, x: StrideInputs) -> float:
        return self.stride_m


def test_a_model_added_to_the_registry_is_configurable(monkeypatch):
    """docs/extending.md: adding a stride model touches step_length.py alone."""
    monkeypatch.setitem(STRIDE_MODELS, "constant", Constant)
    config = replace(StepLengthConfig(calibrated=True), model="constant")
    assert stride_model(config).length(WALKING_STRIDE) == config.stairs_stride_m
