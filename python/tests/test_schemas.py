"""The report classes of ``ncgear.reports`` agree with the JSON Schemas of ``docs/schemas/`` (the
schemas are generated from the Rust report types, which are the truth; ``reports.py`` is
generated from the schemas by ``scripts/gen_reports.py``, and test_reports_generated.py checks it
is not stale — this walk is a second reading of the schemas, independent of the generator's).

From each schema's root class (named as the schema's ``title``: ``DesignReport`` ↔
``design.schema.json`` …) the check walks every field: the field's JSON key is a property of the
schema and every property is a field, and the annotated type agrees with the property's schema —
``float`` ↔ number, ``int`` ↔ integer, ``str`` ↔ string, ``bool`` ↔ boolean, a nested dataclass
↔ an object (checked the same way, and named as the schema's definition), a tuple ↔ an array of
its items, a numpy array ↔ an array of numbers (of any depth), a dict ↔ a map. ``Optional`` ↔ a
property that may be ``null`` or absent; a field that is not ``Optional`` may only be absent when
it reads as empty (a tuple, an array, a dict), and only be ``null`` when it is a ``float`` (a
number that is not finite, read as ``math.inf``). Every class of ``ncgear.reports`` is reached
from a root.
"""
import dataclasses
import json
import pathlib
import re
import typing

import numpy as np
import pytest

from ncgear import reports

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCHEMAS = ROOT / "docs" / "schemas"
FILES = sorted(p.name for p in SCHEMAS.glob("*.schema.json"))


def load(name):
    return json.loads((SCHEMAS / name).read_text())


class Walk:
    """Compares the classes reached from one root with its schema; collects the disagreements."""

    def __init__(self, root_schema, file=""):
        self.root = root_schema
        # A definition two schemas give different shapes is prefixed with its file's stem.
        self.prefix = "".join(w.capitalize() for w in file[: -len(".schema.json")].split("_"))
        self.problems = []
        self.seen = set()

    def resolve(self, s):
        while isinstance(s, dict) and "$ref" in s:
            ref = s["$ref"]
            assert ref.startswith("#/$defs/"), ref
            extra = {k: v for k, v in s.items() if k not in ("$ref", "description")}
            s = {**self.root["$defs"][ref[len("#/$defs/"):]], **extra}
        return s

    def split_null(self, s):
        """(schema without its null alternative — a reference left as it is —, whether null is
        allowed)."""
        r = self.resolve(s)
        t = r.get("type")
        if isinstance(t, list) and "null" in t:
            rest = [x for x in t if x != "null"]
            return {**r, "type": rest[0] if len(rest) == 1 else rest}, True
        for key in ("anyOf", "oneOf"):
            alts = r.get(key)
            if alts and any(self.resolve(a).get("type") == "null" for a in alts):
                rest = [a for a in alts if self.resolve(a).get("type") != "null"]
                return (rest[0] if len(rest) == 1 else {key: rest}), True
        return s, False

    def is_number_array(self, s):
        s = self.resolve(s)
        if s.get("type") != "array":
            return False
        items = s.get("items")
        if items is None and "prefixItems" in s:
            return all(self.is_number_array(i) or self.resolve(i).get("type") in ("number", "integer")
                       for i in s["prefixItems"])
        if items is None:
            return False
        i = self.resolve(items)
        return i.get("type") in ("number", "integer") or self.is_number_array(i)

    def fail(self, path, msg):
        self.problems.append(f"{path}: {msg}")

    def check_class(self, cls, schema, path):
        schema = self.resolve(schema)
        self.seen.add(cls.__name__)
        # A flattened enum (a trade-off row's `designed` or `refused`): each variant's keys are
        # keys of the object, present in some rows only.
        variants = {}
        for alt in schema.get("oneOf", []) + schema.get("anyOf", []):
            variants.update(self.resolve(alt).get("properties", {}))
        props = {**variants, **schema.get("properties", {})}
        required = set(schema.get("required", []))
        hints = typing.get_type_hints(cls)
        keys = {}
        for f in dataclasses.fields(cls):
            keys[reports.json_key(f)] = f
        for key in sorted(set(props) - set(keys)):
            self.fail(f"{path}.{key}", f"a key of the schema without a field of {cls.__name__}")
        for key, f in keys.items():
            if key not in props:
                self.fail(f"{path}.{key}", f"field {cls.__name__}.{f.name} is no key of the schema")
                continue
            self.check_field(hints[f.name], props[key], key in required, f"{path}.{key}")

    def check_field(self, tp, s, required, path):
        inner, nullable = self.split_null(s)
        origin, args = typing.get_origin(tp), typing.get_args(tp)
        optional = origin is typing.Union and type(None) in args
        if optional:
            rest = [a for a in args if a is not type(None)]
            tp = rest[0] if len(rest) == 1 else typing.Union[tuple(rest)]
            origin, args = typing.get_origin(tp), typing.get_args(tp)
            if required and not nullable:
                self.fail(path, "Optional in Python but always written (required, not null)")
        else:
            empty_ok = origin in (tuple, dict) or tp is np.ndarray or origin is np.ndarray
            if not required and not empty_ok:
                self.fail(path, f"{tp} in Python but may be absent from the JSON: Optional")
            if nullable and tp is not float:
                self.fail(path, f"{tp} in Python but may be null in the JSON: Optional")
        self.check_type(tp, inner, path)

    def check_type(self, tp, s, path):
        ref = s.get("$ref", "").rsplit("/", 1)[-1] if isinstance(s, dict) else ""
        s = self.resolve(s)
        origin, args = typing.get_origin(tp), typing.get_args(tp)
        t = s.get("type")
        if isinstance(tp, type) and dataclasses.is_dataclass(tp):
            if ref and tp.__name__ != ref and tp.__name__ != self.prefix + ref:
                self.fail(path, f"class {tp.__name__} for the definition {ref}")
            if t != "object" or "properties" not in s:
                self.fail(path, f"dataclass {tp.__name__} but the schema is {json.dumps(s)[:120]}")
            else:
                self.check_class(tp, s, path)
        elif tp is np.ndarray or origin is np.ndarray:
            if not self.is_number_array(s):
                self.fail(path, f"numpy array but the schema is {json.dumps(s)[:120]}")
        elif origin is tuple:
            if t != "array":
                self.fail(path, f"tuple but the schema is {json.dumps(s)[:120]}")
            elif len(args) == 2 and args[1] is Ellipsis:
                if "items" not in s:
                    self.fail(path, "Tuple[X, ...] but the schema's array has no items")
                else:
                    self.check_type(args[0], s["items"], f"{path}[]")
            else:
                n = len(args)
                if "prefixItems" in s:
                    items = s["prefixItems"]
                elif s.get("minItems") == n and s.get("maxItems") == n and "items" in s:
                    items = [s["items"]] * n
                else:
                    self.fail(path, f"a tuple of {n} but the schema's array is not of length {n}")
                    return
                if len(items) != n:
                    self.fail(path, f"a tuple of {n} but the schema's array has {len(items)}")
                for k, (a, i) in enumerate(zip(args, items)):
                    self.check_type(a, i, f"{path}[{k}]")
        elif origin is dict:
            ap = s.get("additionalProperties")
            if t != "object" or not isinstance(ap, dict):
                self.fail(path, f"dict but the schema is no map: {json.dumps(s)[:120]}")
            elif args and args[1] is not typing.Any:
                self.check_type(args[1], ap, f"{path}{{}}")
        elif origin is typing.Union:
            # A value of several shapes (an enum written as a string or a one-key object).
            alts = [self.resolve(a) for a in s.get("oneOf", s.get("anyOf", []))]
            kinds = {a.get("type") for a in alts}
            for a in args:
                want = {str: "string", dict: "object"}.get(typing.get_origin(a) or a)
                if want not in kinds:
                    self.fail(path, f"{a} in the Union but no {want} alternative in the schema")
        elif tp is typing.Any:
            pass
        else:
            want = {float: ("number",), int: ("integer",), str: ("string",), bool: ("boolean",)}
            ok = want.get(tp)
            if ok is None:
                self.fail(path, f"unchecked annotation {tp}")
            elif t not in ok and not (tp is str and "enum" in s or tp is str and "const" in s):
                alts = [self.resolve(a) for a in s.get("oneOf", [])]
                if not (tp is str and alts and all(a.get("type") == "string" for a in alts)):
                    self.fail(path, f"{tp.__name__} in Python but {json.dumps(s)[:120]} in the schema")


def root_class(file):
    """The class of a schema's root: named as its ``title``."""
    title = load(file)["title"]
    assert hasattr(reports, title), f"{file}: no class {title} in ncgear.reports"
    return getattr(reports, title)


@pytest.mark.parametrize("file", FILES)
def test_class_agrees_with_its_schema(file):
    schema = load(file)
    w = Walk(schema, file)
    w.check_class(root_class(file), schema, file[: -len(".schema.json")])
    assert not w.problems, "\n".join(w.problems)


def test_every_class_is_checked_and_every_schema_has_its_class():
    assert len(FILES) >= 14, FILES  # every report of docs/schemas.md
    seen = set()
    for file in FILES:
        w = Walk(load(file), file)
        w.check_class(root_class(file), load(file), file)
        seen |= w.seen
    classes = {
        name for name, c in vars(reports).items()
        if isinstance(c, type) and dataclasses.is_dataclass(c) and c.__module__ == reports.__name__
    }
    assert classes - seen == set(), f"classes checked against no schema: {classes - seen}"
    assert set(reports.__all__) == classes | {"Numbers", "Points", "Vectors", "build", "json_key"}


def test_the_walk_finds_a_disagreement():
    """The check is real: a field of the wrong type, a missing key, an extra field, a class not
    named as its definition and a nullable field not ``Optional`` fail."""
    schema = load("pair.schema.json")

    @dataclasses.dataclass(frozen=True)
    class Wrong:
        schema_version: str  # an integer in the schema
        z: int
        extra_field: float  # no key of the schema
        verdict: reports.LoadsUnits  # the definition Verdict
        sector: reports.SectorReport  # null without a sector

    w = Walk(schema, "pair.schema.json")
    w.check_class(Wrong, schema, "pair")
    text = "\n".join(w.problems)
    assert "pair.schema_version: str in Python" in text, text
    assert "pair.extra_field: field Wrong.extra_field is no key" in text, text
    assert "pair.module_mm: a key of the schema without a field" in text, text
    assert "pair.verdict: class LoadsUnits for the definition Verdict" in text, text
    assert "pair.sector: <class 'ncgear.reports.SectorReport'> in Python but may be null" in text, text


def test_the_class_renames_are_documented_and_done():
    """docs/schemas.md lists the hand-written classes' old names and the generated ones: each new
    name is a class, no old name is left (no silent alias)."""
    text = (ROOT / "docs" / "schemas.md").read_text(encoding="utf-8")
    section = text.split("### Python class renames", 1)[1].split("\n## ", 1)[0]
    pairs = re.findall(r"`(\w+)` \| `(\w+)`", section)
    assert len(pairs) == 30, pairs
    for old, new in pairs:
        assert isinstance(getattr(reports, new, None), type), f"{new} (was {old}) is no class"
        assert not hasattr(reports, old), f"{old} (now {new}) is still a name of ncgear.reports"
