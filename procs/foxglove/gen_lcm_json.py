#!/usr/bin/env python3
"""Generates the JSON view of every ucon LCM type: ucon/foxglove/lcm_json_gen.{hpp,cpp}.

For each type of lcmtypes/*.lcm it writes
  * writeJson(const T&, JsonWriter&): the message as one JSON object, field names as in the
    .lcm file (numbers, strings, booleans; `byte` arrays as base64 strings; nested types as
    objects; variable-length arrays as arrays),
  * the type's jsonschema (draft-07 keywords, one "type" string per property, so that Foxglove
    can build its message definitions from it), with each field's .lcm comment (its unit and
    the value meaning "invalid") as the description, and the constants a field refers to
    ("STATE_* below") listed in that field's description,
  * a table LcmTypeInfo {name, fingerprint, schema, decode-and-write, has message time} over
    all types; a type has message time when its first field is `int64_t utime` whose comment
    does not call it wall clock (log_metadata_t and supervisor_status_t do).

JSON has no NaN or infinity: non-finite numbers are written as null (the schema's descriptions
say so once, in the type's description).

usage: gen_lcm_json.py OUT_HEADER OUT_SOURCE file.lcm...
"""
import json
import os
import re
import sys

INTEGER = {"int8_t", "int16_t", "int32_t", "int64_t"}
NUMBER = {"float", "double"}
PRIMITIVES = INTEGER | NUMBER | {"string", "boolean", "byte"}
NON_FINITE_NOTE = "Non-finite numbers (NaN, infinity) are written as null."


def parse(path):
    """Returns (package, name, description, fields, constants) of one .lcm file.

    fields: [(type, name, length_field or None, comment)], constants: [(name, value, comment)].
    """
    lines = open(path).read().splitlines()
    pkg = None
    name = None
    desc = []
    fields = []
    consts = []
    in_struct = False
    pending_block = False
    for raw in lines:
        line = raw.strip()
        if pending_block:
            if "*/" in line:
                pending_block = False
            continue
        if line.startswith("/*"):
            pending_block = "*/" not in line
            continue
        code, _, comment = line.partition("//")
        code = code.strip()
        comment = comment.strip()
        if not in_struct:
            m = re.match(r"package\s+(\w+)\s*;", code)
            if m:
                pkg = m.group(1)
                continue
            m = re.match(r"struct\s+(\w+)", code)
            if m:
                name = m.group(1)
                in_struct = True
                continue
            if not code and comment:
                desc.append(comment)
            continue
        if code in ("{", "}", ""):
            if not code and comment and fields:
                # A comment line of its own continues the previous field's comment.
                t, n, d, c = fields[-1]
                fields[-1] = (t, n, d, (c + " " + comment).strip())
            continue
        code = code.rstrip(";").strip()
        m = re.match(r"const\s+[\w.]+\s+(\w+)\s*=\s*([^;]+)$", code)
        if m:
            consts.append((m.group(1), m.group(2).strip(), comment))
            continue
        m = re.match(r"([\w.]+)\s+(\w+)\s*((?:\[\s*\w+\s*\])*)$", code)
        if not m:
            raise SystemExit(f"{path}: cannot parse '{code}'")
        ftype, fname, dims = m.group(1), m.group(2), re.findall(r"\[\s*(\w+)\s*\]", m.group(3))
        if len(dims) > 1:
            raise SystemExit(f"{path}: multi-dimensional arrays are not supported ({fname})")
        if "." in ftype:
            ftype = ftype.split(".")[-1]
        fields.append((ftype, fname, dims[0] if dims else None, comment))
    if not pkg or not name:
        raise SystemExit(f"{path}: no package or struct")
    return pkg, name, " ".join(desc), fields, consts


def describe(comment, consts):
    """The field's comment, with the constants it refers to (PREFIX_* ...) spelled out."""
    text = comment
    for prefix in re.findall(r"\b([A-Z][A-Z0-9]*)_\*", comment):
        listed = [f"{n} = {v}" + (f" ({c})" if c else "")
                  for n, v, c in consts if n.startswith(prefix + "_")]
        if listed:
            text += ": " + "; ".join(listed)
    return text


def schema_of(name, types, top):
    pkg, _, desc, fields, consts = types[name]
    props = {}
    for ftype, fname, dim, comment in fields:
        if ftype in types:
            item = schema_of(ftype, types, False)
        elif ftype in INTEGER:
            item = {"type": "integer"}
        elif ftype in NUMBER:
            item = {"type": "number"}
        elif ftype == "string":
            item = {"type": "string"}
        elif ftype == "boolean":
            item = {"type": "boolean"}
        elif ftype == "byte":
            item = {"type": "integer", "minimum": 0, "maximum": 255}
        else:
            raise SystemExit(f"{name}.{fname}: unknown type {ftype}")
        if dim is None:
            prop = dict(item)
        elif ftype == "byte":
            prop = {"type": "string", "contentEncoding": "base64"}
        else:
            prop = {"type": "array", "items": item}
        text = describe(comment, consts)
        if dim is not None and ftype == "byte":
            text = (text + " " if text else "") + "(bytes, base64)"
        if text:
            prop["description"] = text
        props[fname] = prop
    out = {"title": f"{pkg}.{name}", "type": "object"}
    d = desc
    unused = [c for c in consts if not any(
        re.search(r"\b" + c[0].split("_")[0] + r"_\*", f[3]) for f in fields)]
    if unused:
        d += " Constants: " + "; ".join(f"{n} = {v}" for n, v, _ in unused) + "."
    if top:
        d = (d + " " if d else "") + NON_FINITE_NOTE
    if d:
        out["description"] = d
    out["properties"] = props
    out["required"] = [f[1] for f in fields]
    out["additionalProperties"] = False
    return out


def has_message_time(t):
    """True when the type's first field is `int64_t utime` in message time (not wall clock)."""
    fields = t[3]
    if not fields:
        return False
    ftype, fname, dim, comment = fields[0]
    return ftype == "int64_t" and fname == "utime" and dim is None and "wall clock" not in comment


def writer_lines(name, types):
    _, _, _, fields, _ = types[name]
    out = [f"void writeJson(const {name}& m, JsonWriter& w) {{", "  w.beginObject();"]

    def one(ftype, expr):
        if ftype in types:
            return f"writeJson({expr}, w);"
        if ftype in INTEGER:
            return f"w.integer({expr});"
        if ftype in NUMBER:
            return f"w.number({expr});"
        if ftype == "string":
            return f"w.string({expr});"
        if ftype == "boolean":
            return f"w.boolean({expr} != 0);"
        if ftype == "byte":
            return f"w.integer({expr});"
        raise SystemExit(f"{name}: unknown type {ftype}")

    for ftype, fname, dim, _ in fields:
        out.append(f'  w.key("{fname}");')
        if dim is None:
            out.append("  " + one(ftype, f"m.{fname}"))
        elif ftype == "byte":
            out.append(f"  w.base64(m.{fname}.data(), m.{fname}.size());")
        elif ftype in NUMBER:
            out.append(f"  w.numberArray(m.{fname}.data(), m.{fname}.size());")
        elif ftype in INTEGER:
            out.append(f"  w.integerArray(m.{fname}.data(), m.{fname}.size());")
        else:
            out.append("  w.beginArray();")
            out.append(f"  for (const auto& v : m.{fname}) {one(ftype, 'v')}")
            out.append("  w.endArray();")
    out.append("  w.endObject();")
    out.append("}")
    return out


def main():
    out_h, out_cpp, files = sys.argv[1], sys.argv[2], sys.argv[3:]
    parsed = [parse(f) for f in files]
    types = {p[1]: p for p in parsed}
    names = sorted(types)

    h = ["// Generated by procs/foxglove/gen_lcm_json.py from lcmtypes/*.lcm. Do not edit.",
         "#pragma once", ""]
    for n in names:
        h.append(f'#include "ucon/{n}.hpp"')
    h += ["", "namespace ucon {", "namespace foxglove {", "", "class JsonWriter;", ""]
    for n in names:
        h.append(f"/// {types[n][0]}.{n} as one JSON object (field names as in the .lcm file).")
        h.append(f"void writeJson(const {n}& m, JsonWriter& w);")
    h += ["", "}  // namespace foxglove", "}  // namespace ucon", ""]

    c = ["// Generated by procs/foxglove/gen_lcm_json.py from lcmtypes/*.lcm. Do not edit.",
         '#include "ucon/foxglove/lcm_json_gen.hpp"', "",
         '#include "ucon/foxglove/json_writer.hpp"',
         '#include "ucon/foxglove/lcm_json.hpp"', "",
         "namespace ucon {", "namespace foxglove {", ""]
    for n in names:
        c += writer_lines(n, types)
        c.append("")
    c += ["namespace {", "",
          "template <class T>",
          "bool decodeAndWrite(const void* data, int size, JsonWriter& w) {",
          "  T m{};",
          "  if (m.decode(data, 0, size) != size) return false;",
          "  writeJson(m, w);",
          "  return true;",
          "}", "", "}  // namespace", "",
          "const std::vector<LcmTypeInfo>& lcmTypes() {",
          "  static const std::vector<LcmTypeInfo> kTypes = {"]
    for n in names:
        schema = json.dumps(schema_of(n, types, True), separators=(",", ":"), ensure_ascii=False)
        if ")ucon_schema\"" in schema:
            raise SystemExit(f"{n}: schema text contains the raw-string delimiter")
        c.append(f'      {{"{types[n][0]}.{n}", {n}::getHash(), R"ucon_schema({schema})ucon_schema",')
        c.append(f"       &decodeAndWrite<{n}>, {'true' if has_message_time(types[n]) else 'false'}}},")
    c += ["  };", "  return kTypes;", "}", "", "}  // namespace foxglove", "}  // namespace ucon", ""]

    for path, text in ((out_h, h), (out_cpp, c)):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        tmp = path + ".tmp"
        with open(tmp, "w") as f:
            f.write("\n".join(text))
        os.replace(tmp, path)


if __name__ == "__main__":
    main()
