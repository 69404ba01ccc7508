"""Pydantic validation errors as one readable message: the file, the dotted key, the problem."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any, TypeVar

import yaml
from pydantic import BaseModel, ValidationError

from anytip.errors import AnytipError


def model_at(model: type[BaseModel], loc: tuple[Any, ...]) -> type[BaseModel]:
    """The (sub)model that owns the key at the pydantic error location `loc`.

    Walks nested fields whose annotation is a model, or a union containing one
    (`Sub | None`); stops at the first part that is not a nested model.
    """
    for part in loc[:-1]:
        field = model.model_fields.get(str(part))
        ann = getattr(field, "annotation", None)
        nxt = next((c for c in (ann, *getattr(ann, "__args__", ()))
                    if isinstance(c, type) and issubclass(c, BaseModel)), None)
        if nxt is None:
            break
        model = nxt
    return model


def describe_error(err: dict[str, Any], model: type[BaseModel]) -> str:
    """One pydantic error as `key 'a.b': problem`, listing the allowed keys for unknown ones."""
    loc = tuple(err["loc"])
    key = ".".join(str(p) for p in loc) or "(top level)"
    owner = model_at(model, loc)
    if err["type"] == "extra_forbidden":
        return f"key '{key}' is not allowed; allowed keys: {', '.join(sorted(owner.model_fields))}"
    field = owner.model_fields.get(str(loc[-1])) if loc else None
    hint = f" ({field.description})" if field is not None and field.description else ""
    return f"key '{key}'{hint}: {err['msg']} (got {err.get('input')!r})"


def format_validation_error(err: ValidationError, source: str, model: type[BaseModel],
                            what: str = "") -> str:
    """`source: [what: ]problem; problem ...` for every error of `err`."""
    prefix = f"{source}: {what + ': ' if what else ''}"
    return mask_secrets(prefix + "; ".join(describe_error(e, model) for e in err.errors()))


NAME_PATTERN = r"^[A-Za-z0-9_-][A-Za-z0-9._-]{0,127}$"  # a file or directory name: no '/', no leading '.'


class _SpecLoader(yaml.SafeLoader):
    """Safe YAML without aliases (a few bytes of `*a` can expand to gigabytes once copied)
    and with YAML 1.2 floats (`1e-3` is a number, not the string PyYAML 1.1 makes of it)."""

    def compose_node(self, parent: Any, index: Any) -> Any:
        if self.check_event(yaml.AliasEvent):
            mark = self.peek_event().start_mark
            raise yaml.composer.ComposerError(None, None, "aliases (*name) are not allowed here", mark)
        return super().compose_node(parent, index)


_SpecLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)?(?:\.[0-9_]*)?[eE][-+]?[0-9]+$|^[-+]?\.(?:inf|Inf|INF)$"
               r"|^\.(?:nan|NaN|NAN)$|^[-+]?[0-9][0-9_]*\.[0-9_]*$|^[-+]?\.[0-9_]+$"),
    list("-+0123456789."),
)


def load_yaml(text: str, source: str) -> Any:
    """Parse `text` as safe YAML (no aliases); a syntax error names `source` and the line."""
    try:
        return yaml.load(text, Loader=_SpecLoader)  # noqa: S506 - a SafeLoader subclass
    except yaml.YAMLError as e:
        text = " ".join(str(e).replace('in "<unicode string>", ', "").split())
        raise AnytipError(f"{source}: not valid YAML: {text}") from None


def read_yaml(path: Path) -> dict[str, Any]:
    """A YAML mapping from `path` (safe, no aliases), or an AnytipError naming the file."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise AnytipError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as e:
        raise AnytipError(f"{path}: cannot read ({e})") from None
    data = load_yaml(text, str(path))
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise AnytipError(f"{path}: expected a mapping of keys to values, got {type(data).__name__}")
    return data


M = TypeVar("M", bound=BaseModel)


def validate_strict(model: type[M], data: Any, source: str, what: str = "") -> M:
    """`model` from `data` with no silent coercion: `true` is not a number, `"3"` not an
    integer, `.inf` and `.nan` are refused (models set allow_inf_nan=False or bound values);
    an error names `source`, the dotted key and what is allowed.

    Validated as JSON in strict mode, which takes lists for tuples as YAML gives them.
    """
    try:
        text = json.dumps(data, default=str)
    except (TypeError, ValueError) as e:
        where = f"{source}: {what + ': ' if what else ''}"
        raise AnytipError(f"{where}cannot be read as plain values: {e}") from None
    try:
        return model.model_validate_json(text, strict=True)
    except ValidationError as e:
        raise AnytipError(format_validation_error(e, source, model, what)) from None


_URL_PASSWORD = re.compile(r"(?P<head>[A-Za-z][A-Za-z0-9+.-]*://[^:/@\s]*):(?P<secret>[^@\s]*)@")


def mask_secrets(value: Any) -> Any:
    """`value` with the password of every URL in it (`scheme://user:password@host`) replaced by
    `***`; strings, lists and mappings are walked, other values returned as they are."""
    if isinstance(value, str):
        return _URL_PASSWORD.sub(lambda m: f"{m['head']}:***@", value)
    if isinstance(value, dict):
        return {k: mask_secrets(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [mask_secrets(v) for v in value]
    return value
