"""Experiment specs: composition, overrides, and errors that name file, key and allowed values."""

from pathlib import Path

import pytest

from anytip.config import load_spec
from anytip.errors import AnytipError

REPO = Path(__file__).resolve().parents[1]


def write(tmp_path: Path, text: str) -> Path:
    (tmp_path / "configs").symlink_to(REPO / "configs")
    path = tmp_path / "exp.yaml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("spec", sorted((REPO / "experiments").glob("*.yaml")), ids=lambda p: p.stem)
def test_every_committed_spec_validates(spec):
    assert load_spec(spec).pipeline


def test_blocks_compose_and_override(tmp_path):
    spec = load_spec(write(tmp_path, "pipeline: baseline\ntraining: {use: paper, epochs: 3}\n"),
                     ["training.lr=0.01", "seeds=[1, 2]"])
    assert (spec.training.name, spec.training.epochs, spec.training.batch_size) == ("paper", 3, 10)
    assert spec.training.lr == 0.01 and spec.all_seeds == [1, 2]
    assert spec.name == "exp"


def test_unknown_key_names_file_key_and_allowed(tmp_path):
    path = write(tmp_path, "pipeline: baseline\nsplits: {n_tset_units: 2}\n")
    with pytest.raises(AnytipError) as e:
        load_spec(path)
    msg = str(e.value)
    assert str(path) in msg and "splits.n_tset_units" in msg and "n_test_units" in msg


def test_wrong_type_and_bad_value(tmp_path):
    with pytest.raises(AnytipError, match=r"training.epochs.*got 'many'"):
        load_spec(write(tmp_path, "pipeline: baseline\ntraining: {use: fast, epochs: many}\n"))
    with pytest.raises(AnytipError, match=r"pipeline.*'baseline'.*got 'nope'"):
        load_spec(tmp_path / "exp.yaml", ["pipeline=nope"])
    with pytest.raises(AnytipError, match=r"splits.test_rows.*'test_session'.*'all_sessions'.*got 'both'"):
        load_spec(tmp_path / "exp.yaml", ["splits.test_rows=both"])


def test_all_sessions_needs_the_test_sessions_runs_read(tmp_path):
    """`splits.test_rows: all_sessions` with a `data.protocol` that leaves out `retest` would test every
    unit on its main rows alone: refused, naming both keys; with retest listed or every protocol read,
    taken."""
    path = write(tmp_path, "pipeline: baseline\nsplits: {test_rows: all_sessions}\n")
    said = r"exp.yaml.*splits.test_rows.*all_sessions.*data.protocol.*retest"
    for protocol in ("full", "[full, short, quick]"):
        with pytest.raises(AnytipError, match=said):
            load_spec(path, [f"data.protocol={protocol}"])
    for protocol in ("[full, retest]", "null"):
        assert load_spec(path, [f"data.protocol={protocol}"]).splits.test_rows == "all_sessions"
    assert load_spec(path, ["splits.test_rows=test_session"]).data.protocols == ["full"]


def test_unknown_block_lists_known(tmp_path):
    with pytest.raises(AnytipError, match=r"no block 'quick'; allowed: fast, paper"):
        load_spec(write(tmp_path, "pipeline: baseline\ntraining: quick\n"))


def test_bad_yaml_and_bad_override(tmp_path):
    path = write(tmp_path, "pipeline: [baseline\n")
    with pytest.raises(AnytipError, match="not valid YAML"):
        load_spec(path)
    path.write_text("pipeline: baseline\n")
    with pytest.raises(AnytipError, match="expected key=value"):
        load_spec(path, ["epochs"])


@pytest.mark.parametrize("name", ["paper", "fast"])
def test_recipe_files_equal_the_code_defaults(name):
    from anytip.train.recipe import TrainRecipe, get_recipe
    from anytip.validation import read_yaml

    block = read_yaml(REPO / "configs" / "training" / f"{name}.yaml")
    assert TrainRecipe.model_validate(block) == get_recipe(name)


def test_threads_must_be_positive(tmp_path):
    with pytest.raises(AnytipError, match="threads"):
        load_spec(write(tmp_path, "pipeline: baseline\nthreads: 0\n"))
