"""`taxel schema [scene|study|optimization|rig] [--json]`, and the key reference of the docs.

One generator, read from the pydantic schemas themselves so that it cannot drift:

- `json_schema(kind)`: the JSON Schema of a TOML file kind (for editors: point a
  TOML language server at the printed file);
- `keys(kind)`: every key of the kind, nested tables and arrays of tables
  included, as `Key` rows: dotted path, type, unit (the `unit` carried by the
  quantity validators of `taxel.schema`), default, allowed values (`Literal`),
  bounds (`Field(ge=, gt=, le=, lt=)`) and the key's comment in the schema source;
- `text(kind)`: those rows for a terminal (`taxel schema KIND`): path, type, unit,
  default, then the key's description;
- `markdown(kind)`: those rows as the Markdown page of the docs' reference
  (docs/reference/keys/KIND.md, kept in the repository so that a clone can read it;
  the docs build rewrites it, and tests/test_docs.py checks it is current).

A key's description is its field's docstring (pydantic `use_attribute_docstrings`,
so the JSON Schema carries it too), else its comment in the schema source.
"""

from __future__ import annotations

import importlib
import inspect
import io
import json
import re
import tokenize
import types
import typing
from dataclasses import dataclass
from typing import Annotated, Literal, Union

import annotated_types
from pydantic import BaseModel
from pydantic_core import PydanticUndefined

# kind -> (module, model, what the file is)
KINDS = {
    "scene": ("taxel.scene", "Scene", "a design and its load case (`taxel solve SCENE`)"),
    "study": ("taxel.studies.spec", "StudySpec", "a parameter study (`taxel study run STUDY`)"),
    "optimization": ("taxel.optimize.spec", "OptimizationSpec", "an optimization (`taxel optimize OPT`)"),
    "rig": ("taxel.studies.bench.rig", "Rig", "a measurement bench (`taxel measure ... RIG`)"),
}
_BOUNDS = ((annotated_types.Ge, "ge", ">="), (annotated_types.Gt, "gt", ">"),
           (annotated_types.Le, "le", "<="), (annotated_types.Lt, "lt", "<"),
           (annotated_types.MinLen, "min_length", "length >="), (annotated_types.MaxLen, "max_length", "length <="))


_PLAIN = {str: "string", int: "integer", float: "number", bool: "boolean", dict: "table", typing.Any: "any"}


@dataclass(frozen=True)
class Key:
    """One key of a TOML file kind: `path` is dotted; `[]` marks an array of
    tables, `<name>` a table keyed by the user's names."""

    path: str
    type: str
    unit: str
    default: str
    allowed: str
    bounds: str
    doc: str
    table: bool            # a table of further keys (its keys follow it)


def model(kind: str) -> type[BaseModel]:
    """The pydantic model of a file kind (one of KINDS)."""
    if kind not in KINDS:
        raise ValueError(f"schema {kind!r}: give one of {', '.join(KINDS)}")
    module, name, _ = KINDS[kind]
    return getattr(importlib.import_module(module), name)


def json_schema(kind: str) -> dict:
    """The JSON Schema (draft 2020-12, as pydantic writes it) of a file kind, keys
    by their TOML names."""
    schema = model(kind).model_json_schema(by_alias=True, mode="validation")
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema.setdefault("description", KINDS[kind][2])
    return schema


def _comments(cls: type) -> dict[str, str]:
    """field name -> its comment in the class source (on its line, or full-line
    comments just above it)."""
    try:
        source = inspect.getsource(cls)
    except (OSError, TypeError):
        return {}
    found: dict[str, str] = {}
    pending: list[str] = []
    lines = source.splitlines()
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type != tokenize.COMMENT:
            continue
        text = tok.string.lstrip("#").strip()
        line = lines[tok.start[0] - 1]
        m = re.match(r"\s+(\w+)\s*:", line)
        if line.strip().startswith("#"):
            pending.append(text)
            nxt = lines[tok.start[0]] if tok.start[0] < len(lines) else ""
            m2 = re.match(r"\s+(\w+)\s*:", nxt)
            if m2:
                found[m2.group(1)] = " ".join(pending)
                pending = []
        elif m:
            found[m.group(1)] = text
            pending = []
    return found


def _parts(tp) -> tuple[list, list]:
    """(the plain types inside an annotation, its metadata) through Annotated,
    Optional/Union, tuple, list and dict values."""
    origin = typing.get_origin(tp)
    if origin is Annotated:
        base, *meta = typing.get_args(tp)
        types_, inner = _parts(base)
        return types_, meta + inner
    if origin in (Union, types.UnionType):
        out, meta = [], []
        for a in typing.get_args(tp):
            t, m = _parts(a)
            out += t
            meta += m
        return out, meta
    return [tp], []


def _type_name(tp) -> str:
    origin = typing.get_origin(tp)
    if origin is Annotated:
        return _type_name(typing.get_args(tp)[0])
    if origin in (Union, types.UnionType):
        return " or ".join(_type_name(a) for a in typing.get_args(tp))
    if origin is Literal:
        return " or ".join(dict.fromkeys(_PLAIN.get(type(a), type(a).__name__) for a in typing.get_args(tp)))
    if origin in (list, tuple, dict):
        args = [a for a in typing.get_args(tp) if a is not Ellipsis]
        inner = ", ".join(_type_name(a) for a in args)
        name = {list: "array", tuple: "array", dict: "table"}[origin]
        return f"{name} of {inner}" if inner else name
    if tp is type(None):
        return "none"
    if isinstance(tp, type) and issubclass(tp, BaseModel):
        return "table"
    return _PLAIN.get(tp, getattr(tp, "__name__", str(tp)))


def _walk_meta(tp) -> tuple[str, list[str], list[str]]:
    """(unit, allowed values, bounds) found anywhere in an annotation."""
    unit, allowed, bounds = "", [], []

    def visit(t):
        nonlocal unit
        origin = typing.get_origin(t)
        if origin is Annotated:
            base, *meta = typing.get_args(t)
            for m in meta:
                unit = unit or _unit(m)
                bounds.extend(_bound_text(m))
            visit(base)
        elif origin is Literal:
            allowed.extend(json.dumps(a) for a in typing.get_args(t))
        elif origin is not None:
            for a in typing.get_args(t):
                if a is not Ellipsis:
                    visit(a)
    visit(tp)
    return unit, allowed, bounds


def _unit(meta) -> str:
    """The SI unit a quantity validator converts to: its `unit` attribute
    (taxel.schema), or the `unit` its closure holds (validators built the same way)."""
    func = getattr(meta, "func", None)
    if func is None:
        return ""
    if getattr(func, "unit", None):
        return func.unit
    try:
        return str(inspect.getclosurevars(func).nonlocals.get("unit", "") or "")
    except TypeError:
        return ""


def _bound_text(meta) -> list[str]:
    out = []
    checked = getattr(getattr(meta, "func", None), "bounds", {})      # a dimensionless quantity's own bounds
    for attr, sym in (("ge", ">="), ("gt", ">"), ("le", "<="), ("lt", "<")):
        if attr in checked:
            out.append(f"{sym} {checked[attr]:g}")
    for cls, attr, sym in _BOUNDS:
        if isinstance(meta, cls):
            out.append(f"{sym} {getattr(meta, attr)}")
    for attr, sym in (("ge", ">="), ("gt", ">"), ("le", "<="), ("lt", "<")):   # annotated_types.Interval
        if type(meta).__name__ == "Interval" and getattr(meta, attr, None) is not None:
            out.append(f"{sym} {getattr(meta, attr)}")
    return out


def _default(info) -> str:
    if info.default_factory is not None:
        value = info.default_factory()
    elif info.default is PydanticUndefined:
        return "required"
    else:
        value = info.default
    if isinstance(value, BaseModel):
        return "(table)"
    if value is None:
        return "none"
    if isinstance(value, tuple):
        value = list(value)
    return json.dumps(value) if not isinstance(value, str) else f'"{value}"'


def _submodels(tp) -> list[tuple[str, type[BaseModel]]]:
    """The models nested in an annotation, with the path suffix that reaches
    them: "" (a table), "[]" (an array of tables), ".<name>" (a table of tables)."""
    origin = typing.get_origin(tp)
    if isinstance(tp, type) and issubclass(tp, BaseModel):
        return [("", tp)]
    if origin is Annotated:
        return _submodels(typing.get_args(tp)[0])
    if origin in (Union, types.UnionType):
        return [s for a in typing.get_args(tp) for s in _submodels(a)]
    if origin is list:
        return [("[]" + suffix, m) for suffix, m in _submodels(typing.get_args(tp)[0])]
    if origin is dict:
        return [(".<name>" + suffix, m) for suffix, m in _submodels(typing.get_args(tp)[1])]
    return []


def model_keys(cls: type[BaseModel], prefix: str = "") -> list[Key]:
    """Every key of a model and of the models nested in it, depth first."""
    rows: list[Key] = []
    docs = _comments(cls)
    for name, info in cls.model_fields.items():
        key = info.alias or name
        unit, allowed, bounds = _walk_meta(info.annotation)
        for m in info.metadata:
            unit = unit or _unit(m)
            bounds.extend(_bound_text(m))
        nested = _submodels(info.annotation)
        path = f"{prefix}{key}"
        rows.append(Key(path=path, type=_type_name(info.annotation), unit=unit, default=_default(info),
                        allowed=" | ".join(dict.fromkeys(allowed)), bounds=", ".join(dict.fromkeys(bounds)),
                        doc=" ".join((info.description or docs.get(name, "")).split()), table=bool(nested)))
        for suffix, sub in nested:
            rows += model_keys(sub, f"{path}{suffix}.")
    return rows


def keys(kind: str) -> list[Key]:
    """Every key of a file kind (see `Key`)."""
    return model_keys(model(kind))


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def markdown(kind: str) -> str:
    """The reference page of a file kind: one table row per key."""
    cls = model(kind)
    lines = [f"# {kind.capitalize()} keys", "",
             f"A{'n' if kind[0] in 'aeiou' else ''} {kind} file is {KINDS[kind][2]}. This page is generated from the schema "
             f"(`{cls.__module__}.{cls.__name__}`) at every docs build; `taxel schema {kind}` prints "
             "the same schema as JSON Schema. Quantities are strings with a unit in a file "
             '("0.5 mm"), SI numbers from Python; a key of type *table* holds the keys below it.', "",
             "| key | type | unit | default | allowed | bounds | what it is |",
             "|---|---|---|---|---|---|---|"]
    for k in keys(kind):
        lines.append("| " + " | ".join(_cell(c) for c in (
            f"`{k.path}`", k.type, k.unit, f"`{k.default}`" if k.default not in ("required", "(table)") else k.default,
            k.allowed, k.bounds, k.doc)) + " |")
    # one example per table: the schema module's KEY_EXAMPLES ({title: TOML text})
    examples = getattr(importlib.import_module(cls.__module__), "KEY_EXAMPLES", {})
    if examples:
        lines += ["", "## Examples", ""]
        for title, text in examples.items():
            lines += [f"### {title}", "", "```toml", text.strip("\n"), "```", ""]
    return "\n".join(lines).rstrip("\n") + "\n"


def text(kind: str) -> str:
    """Every key of a file kind for a terminal: its dotted path, then its type, unit,
    default, allowed values and bounds, then its one-line description."""
    lines = [f"The keys of a{'n' if kind[0] in 'aeiou' else ''} {kind} file ({KINDS[kind][2].split(' (')[0]}); quantities are strings with a unit (\"0.5 mm\").",
             "--json prints the JSON Schema; the docs' key reference has the same rows "
             f"(docs/reference/keys/{kind}.md).", ""]
    for k in keys(kind):
        facts = [k.type] + ([f"unit {k.unit}"] if k.unit else [])
        facts += [] if k.default == "(table)" else [k.default if k.default == "required" else f"default {k.default}"]
        facts += [f"one of {k.allowed}"] if k.allowed else []
        facts += [k.bounds] if k.bounds else []
        lines += [f"{k.path}  ({'; '.join(facts)})", f"    {k.doc or '(no description)'}"]
    return "\n".join(lines) + "\n"


def _print(args) -> int:
    print(json.dumps(json_schema(args.kind), indent=2) if args.json else text(args.kind), end="\n" if args.json else "")
    return 0


def register(sub) -> None:
    p = sub.add_parser("schema", help="every key of a scene, study, optimization or rig file: unit, default, "
                                      "description (--json: the JSON Schema, for editors)")
    p.add_argument("kind", nargs="?", default="scene", choices=list(KINDS))
    p.add_argument("--json", action="store_true", help="the JSON Schema instead (point a TOML language server at it)")
    p.set_defaults(run=_print)


__all__ = ["KINDS", "Key", "json_schema", "keys", "markdown", "model", "model_keys", "register", "text"]
