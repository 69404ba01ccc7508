"""Pydantic validation errors as one readable message: the file, the dotted key, the problem."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ValidationError


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
    return prefix + "; ".join(describe_error(e, model) for e in err.errors())
