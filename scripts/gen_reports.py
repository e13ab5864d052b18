#!/usr/bin/env python3
"""Writes python/ncgear/reports.py, the Python report classes, from the JSON Schemas of
docs/schemas/ (themselves generated from the Rust report types: the truth). Stdlib only.

Usage: python3 scripts/gen_reports.py [OUT]   (OUT defaults to python/ncgear/reports.py)
       python3 scripts/gen_reports.py --check   (fails when python/ncgear/reports.py is stale)

One frozen dataclass per object of every schema — its root (named by its ``title``) and each
object definition of ``$defs`` (named as the definition) — sorted by name, fields in the order of
the schema's ``required`` list, then the other keys sorted; docstrings are the ``description``s.
The type rules:

- ``number`` → ``float``, ``integer`` → ``int``, ``string`` → ``str``, ``boolean`` → ``bool``; an
  enum of strings → ``str`` (its values named in the docstring); an enum of strings and one-key
  objects → ``Union[str, Dict[str, Any]]``; a map (``additionalProperties``) → ``Dict[str, X]``.
- An array of numbers, or of rows of numbers, of no fixed length → a read-only float64 numpy
  array: ``Points`` (rows of a point definition, ``[x, y]``), ``Vectors`` (other rows),
  ``Numbers`` (1-D). Any other array (of integers too: indices, counts, flags) →
  ``Tuple[X, ...]``; an array of fixed length → a tuple of that length (a point ``[x, y]`` is
  ``Tuple[float, float]``).
- A key that may be ``null``, or may be absent, is ``Optional`` — but an absent array or map
  reads as empty (not ``Optional`` unless it may also be ``null``). An optional number that may
  be absent reads ``null`` as ``math.inf`` (the key is left out when there is no value, so a
  ``null`` is a number that is not finite); a ``float`` field reads ``null`` as ``math.inf``.
- A definition of the same name in several schemas is one class when the shapes are the same
  (references expanded); when they differ, each shape's class is prefixed with the CamelCase
  stem of the first schema file that has it (``Units`` → ``DesignUnits``, ``LoadsUnits``).
- A class that holds a numpy array, itself or in a nested class, compares by identity
  (``eq=False``).

The generator knows two exceptions by name, its only tables: ``RENAMED_KEYS`` (a JSON key that
is a Python keyword: ``pass`` → the field ``passed``) and ``NULL_IS_INF`` (a check's ``value``,
an f64 the schema declares ``number | null``: a ``float``, not ``Optional``). Every other name is
the schemas'.
"""
from __future__ import annotations

import json
import keyword
import pathlib
import sys
import textwrap

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCHEMAS = ROOT / "docs" / "schemas"
OUT = ROOT / "python" / "ncgear" / "reports.py"
COMMAND = "python3 scripts/gen_reports.py"

# JSON key → field name, for the keys that are no Python identifier (keywords).
RENAMED_KEYS = {"pass": "passed"}
# (class, key) of the numbers a schema declares ``number | null`` that are never absent: an f64
# written as ``null`` when it is not finite (``#[schemars(with = "Option<f64>")]``): a ``float``
# that reads ``null`` as ``math.inf``, not an ``Optional``.
NULL_IS_INF = {("Check", "value")}

NUMPY = ("Points", "Vectors", "Numbers")
# The names reports.py imports: no class may take one.
RESERVED = {"Any", "Dict", "Optional", "Tuple", "Union", "annotations", "build", "dataclass",
            "field", "json_key", *NUMPY}


def camel(stem):
    return "".join(w[:1].upper() + w[1:] for w in stem.split("_"))


class Schema:
    """One schema file: its stem, root and definitions."""

    def __init__(self, path):
        self.stem = path.name[: -len(".schema.json")]
        self.root = json.loads(path.read_text(encoding="utf-8"))
        self.defs = self.root.get("$defs", self.root.get("definitions", {}))

    def resolve(self, s):
        while isinstance(s, dict) and "$ref" in s:
            s = self.defs[s["$ref"].rsplit("/", 1)[1]]
        return s

    def expand(self, s):
        """``s`` with every reference replaced by its definition (the shape, to compare)."""
        if isinstance(s, dict):
            if "$ref" in s:
                name = s["$ref"].rsplit("/", 1)[1]
                rest = {k: self.expand(v) for k, v in s.items() if k != "$ref"}
                return {"$ref": name, "$def": self.expand(self.defs[name]), **rest}
            return {k: self.expand(v) for k, v in s.items()}
        if isinstance(s, list):
            return [self.expand(v) for v in s]
        return s


def is_object(s):
    return "properties" in s


def split_null(sch, s):
    """(``s`` without its ``null`` alternative, whether ``null`` is allowed)."""
    t = s.get("type")
    if isinstance(t, list) and "null" in t:
        rest = [x for x in t if x != "null"]
        return {**s, "type": rest[0] if len(rest) == 1 else rest}, True
    for key in ("anyOf", "oneOf"):
        alts = s.get(key)
        if alts and any(sch.resolve(a).get("type") == "null" for a in alts):
            rest = [a for a in alts if sch.resolve(a).get("type") != "null"]
            assert len(rest) == 1, s
            return rest[0], True
    return s, False


def string_enum(sch, s):
    """The values of an enum of strings, or None."""
    s = sch.resolve(s)
    if s.get("type") == "string" and "enum" in s:
        return list(s["enum"])
    if s.get("type") == "string" and "const" in s:
        return [s["const"]]
    alts = s.get("oneOf", s.get("anyOf"))
    if alts and all(string_enum(sch, a) is not None for a in alts):
        return [v for a in alts for v in string_enum(sch, a)]
    return None


class Gen:
    def __init__(self, paths):
        self.schemas = [Schema(p) for p in paths]
        # (stem, definition or title) → class name; the classes: name → (schema, object schema).
        shapes = {}  # name → {shape: [stems]}
        for sch in self.schemas:
            for name, s in self.objects(sch):
                key = json.dumps(sch.expand(s), sort_keys=True)
                shapes.setdefault(name, {}).setdefault(key, []).append(sch.stem)
        self.names, self.classes, self.prefixed, shape_of = {}, {}, [], {}
        for sch in self.schemas:
            for name, s in self.objects(sch):
                variants = shapes[name]
                key = json.dumps(sch.expand(s), sort_keys=True)
                cls = name if len(variants) == 1 else camel(variants[key][0]) + name
                assert shape_of.setdefault(cls, key) == key, f"the class name {cls} for two shapes"
                self.names[(sch.stem, name)] = cls
                if cls not in self.classes:
                    self.classes[cls] = (sch, s)
                    if cls != name:
                        self.prefixed.append((name, cls, variants[key]))
        for cls in self.classes:
            assert cls.isidentifier() and not keyword.iskeyword(cls) and cls not in RESERVED, cls
        for c, key in NULL_IS_INF:
            assert c in self.classes and key in self.props(c)[0], (c, key)

    @staticmethod
    def objects(sch):
        """(name, schema) of the root and of every object definition."""
        yield sch.root["title"], sch.root
        for name, s in sorted(sch.defs.items()):
            if is_object(s):
                yield name, s

    def props(self, cls):
        """(properties, required keys) of a class: its own and, of a flattened enum, those of
        each variant (never required: a row has one variant's keys; the parts of an ``allOf``
        all apply)."""
        sch, s = self.classes[cls]
        variants, required = {}, list(s.get("required", []))
        for key in ("oneOf", "anyOf", "allOf"):
            for alt in map(sch.resolve, s.get(key, [])):
                for k, p in alt.get("properties", {}).items():  # a key's doc: the variant's
                    doc = p.get("description", alt.get("description"))
                    variants[k] = {**p, "description": doc} if doc else p
                if key == "allOf":  # every part applies: its required keys are
                    required += alt.get("required", [])
        return {**variants, **s.get("properties", {})}, required

    def ann(self, sch, s):
        """(annotation, whether it holds a numpy array, class names it uses) of schema ``s``."""
        if "$ref" in s:
            name = s["$ref"].rsplit("/", 1)[1]
            if (sch.stem, name) in self.names:
                cls = self.names[(sch.stem, name)]
                return cls, False, {cls}
            return self.ann(sch, sch.defs[name])
        inner, nullable = split_null(sch, s)
        if nullable:
            a, arr, used = self.ann(sch, inner)
            return f"Optional[{a}]", arr, used
        if string_enum(sch, s) is not None:
            return "str", False, set()
        alts = s.get("oneOf", s.get("anyOf"))
        if alts:
            kinds = {sch.resolve(a).get("type") for a in alts}
            assert kinds <= {"string", "object"}, s
            return ("Union[str, Dict[str, Any]]" if kinds == {"string", "object"}
                    else "Dict[str, Any]"), False, set()
        t = s.get("type")
        if t == "array":
            return self.array(sch, s)
        if t == "object":
            ap = s.get("additionalProperties")
            assert not is_object(s), f"an inline object: {json.dumps(s)[:200]}"
            if isinstance(ap, dict):
                a, arr, used = self.ann(sch, ap)
                return f"Dict[str, {a}]", arr, used
            return "Dict[str, Any]", False, set()
        simple = {"number": "float", "integer": "int", "string": "str", "boolean": "bool"}
        assert t in simple, f"no type for {json.dumps(s)[:200]}"
        return simple[t], False, set()

    def numeric(self, sch, s):
        """Whether ``s`` is a number or an array of numbers (of any depth)."""
        s = sch.resolve(s)
        if s.get("type") == "number":
            return True
        if s.get("type") != "array":
            return False
        items = s.get("prefixItems", [s["items"]] if "items" in s else [])
        return bool(items) and all(self.numeric(sch, i) for i in items)

    def array(self, sch, s):
        n = s.get("minItems")
        fixed = n is not None and s.get("maxItems") == n
        if not fixed and self.numeric(sch, s):
            items = s["items"]
            if sch.resolve(items).get("type") == "number":
                return "Numbers", True, set()
            row = sch.resolve(items)
            point = "$ref" in items and row.get("minItems") == row.get("maxItems") == 2
            return ("Points" if point else "Vectors"), True, set()
        if "prefixItems" in s:
            parts = [self.ann(sch, i) for i in s["prefixItems"]]
        elif fixed:
            parts = [self.ann(sch, s["items"])] * n
        else:
            a, arr, used = self.ann(sch, s["items"])
            return f"Tuple[{a}, ...]", arr, used
        used = set().union(*(p[2] for p in parts))
        return f"Tuple[{', '.join(p[0] for p in parts)}]", any(p[1] for p in parts), used

    def field(self, cls, key, s, required):
        """(source lines of one field, whether it holds a numpy array, classes used)."""
        sch = self.classes[cls][0]
        inner, nullable = split_null(sch, s)
        a, arr, used = self.ann(sch, inner)
        empty = a.startswith(("Tuple[", "Dict[")) or a in NUMPY
        meta = {}
        if (cls, key) in NULL_IS_INF:
            assert a == "float" and nullable and required, (cls, key)
        elif nullable or not (required or empty):
            if a == "float" and not required:
                meta["null_is_inf"] = True
            a = f"Optional[{a}]"
        name = RENAMED_KEYS.get(key, key)
        assert name.isidentifier() and not keyword.iskeyword(name), key
        if name != key:
            meta["key"] = key
        line = f"    {name}: {a}"
        if meta:
            items = ", ".join(f"{json.dumps(k)}: {py(v)}" for k, v in sorted(meta.items()))
            line += f" = field(metadata={{{items}}})"
        doc = s.get("description", "")
        values = string_enum(sch, inner) or string_enum(sch, sch.resolve(inner).get("items", {}))
        if values:
            doc += ("\n\n" if doc else "") + "One of " + ", ".join(f'``"{v}"``' for v in values) + "."
        return [line] + (docstring(doc, "    ") if doc else []), arr, used

    def render_class(self, cls):
        sch, s = self.classes[cls]
        props, required = self.props(cls)
        order = [k for k in required if k in props] + sorted(k for k in props if k not in required)
        lines, arr, used = [], False, set()
        for key in order:
            ls, a, u = self.field(cls, key, props[key], key in required)
            lines += ls
            arr, used = arr or a, used | u
        doc = s.get("description") or f"``{cls}``."
        if s is sch.root:
            doc += f"\n\nThe root of ``{sch.stem}.schema.json``."
        return doc, lines, arr, used

    def render(self):
        rendered = {c: self.render_class(c) for c in sorted(self.classes)}
        holds = {c: r[2] for c, r in rendered.items()}
        changed = True
        while changed:  # a class holds an array when a class it uses does
            changed = False
            for c, r in rendered.items():
                if not holds[c] and any(holds[u] for u in r[3]):
                    holds[c] = changed = True
        out = [header(self)]
        for c, (doc, lines, _, _) in rendered.items():
            out.append("")
            out.append("")
            out.append("@dataclass(frozen=True, eq=False)" if holds[c] else "@dataclass(frozen=True)")
            out.append(f"class {c}:")
            out += docstring(doc, "    ")
            out.append("")
            out += lines
        names = sorted(list(self.classes) + ["Numbers", "Points", "Vectors", "build", "json_key"])
        out += ["", "", "__all__ = ["]
        out += wrap([json.dumps(n) + "," for n in names], "    ")
        out.append("]")
        return "\n".join(out) + "\n"


def py(v):
    """A str or bool as Python source."""
    return json.dumps(v) if isinstance(v, str) else repr(v)


def docstring(text, indent):
    """``text`` as a triple-quoted docstring at ``indent``."""
    body = text.strip().replace("\\", "\\\\").replace('"""', '\\"\\"\\"')
    if body.endswith('"'):
        body = body[:-1] + '\\"'
    lines = body.split("\n")
    if len(lines) == 1:
        return [f'{indent}"""{body}"""']
    return [f'{indent}"""{lines[0]}'] + [(indent + ln).rstrip() for ln in lines[1:]] + [f'{indent}"""']


def wrap(words, indent, width=100):
    lines, cur = [], indent
    for w in words:
        if cur != indent and len(cur) + 1 + len(w) > width:
            lines.append(cur)
            cur = indent
        cur += ("" if cur == indent else " ") + w
    return lines + [cur]


def para(text, width=100):
    """``text`` (one paragraph) wrapped to ``width`` columns."""
    return "\n".join(textwrap.wrap(text, width, break_long_words=False, break_on_hyphens=False))


def header(gen):
    files = ", ".join(f"``{s.stem}``" for s in gen.schemas)
    roots = "\n".join(
        f"- ``{s.stem}.schema.json``: :class:`{gen.names[(s.stem, s.root['title'])]}`"
        for s in gen.schemas
    )
    prefixed = "\n".join(
        f"- ``{name}`` of {', '.join(f'``{st}``' for st in stems)}: :class:`{cls}`"
        for name, cls, stems in sorted(gen.prefixed, key=lambda p: p[1])
    ) or "- (none)"
    renamed = ", ".join(f"``{k}`` is the field ``{v}``" for k, v in sorted(RENAMED_KEYS.items()))
    paragraphs = [
        "The reports of ncgear as frozen dataclasses, typed and nested as in the JSON files the CLI"
        f" writes: one class per object of the JSON Schemas in ``docs/schemas/`` ({files}), named"
        " as the schema names it, with the JSON keys as fields.",
        f"GENERATED by ``{COMMAND}`` from ``docs/schemas/*.schema.json``: do not edit; regenerate"
        " after the schemas change (python/tests/test_reports_generated.py fails on a stale file)."
        " The rules: the docstring of scripts/gen_reports.py.",
        "Units are in the field names (``_mm``, ``_deg``, ``_rad``, ``_um``, ``_arcsec``, ``_ms``,"
        " ``_N``, ``_Nm``, ``_MPa``, ``_h``); a bare length is in mm and a bare angle in degrees"
        " where the JSON says so (``units``). Number arrays are read-only float64"
        " ``numpy.ndarray``: ``Points`` of shape (N, 2) (``[x, y]``, mm, or a force, N),"
        " ``Vectors`` (rows of a table), ``Numbers`` (1-D); fixed arrays are tuples. A number JSON"
        " writes as ``null`` because it is not finite (an unbounded check value or radius, an"
        " unlimited life) reads as ``math.inf``; a key that may be absent or ``null`` is"
        " ``Optional`` (an absent array or map reads as empty). The JSON key"
        f" {renamed}. How a class is read from its JSON: :func:`build` (:mod:`ncgear._build`).",
        "The root class of each schema:",
        roots,
        "A definition name that schemas give to different shapes, prefixed with the schema's stem:",
        prefixed,
    ]
    text = "\n\n".join(p if p.startswith("- ") else para(p) for p in paragraphs)
    text = para('"""' + paragraphs[0]) + text[len(para(paragraphs[0])):]  # room for the quotes
    return f'''{text}
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Dict, Optional, Tuple, Union

from ._build import Numbers, Points, Vectors, build, json_key'''


def generate(schema_dir=SCHEMAS):
    return Gen(sorted(pathlib.Path(schema_dir).glob("*.schema.json"))).render()


def main(argv):
    if argv[1:] == ["--check"]:
        if OUT.read_text(encoding="utf-8") != generate():
            sys.exit(f"{OUT.relative_to(ROOT)} is stale: the schemas changed; run `{COMMAND}`")
        print(f"{OUT.relative_to(ROOT)} is what {COMMAND} writes")
        return
    out = pathlib.Path(argv[1]) if len(argv) > 1 else OUT
    out.write_text(generate(), encoding="utf-8")
    print(out)


if __name__ == "__main__":
    main(sys.argv)
