#!/usr/bin/env python3
"""Generates the DDS IDL of the PDUs, and the C++ that converts between them and the LCM types,
from the .lcm files: the .lcm files stay the one definition of every PDU (docs/pdu.md).

    lcm_to_idl.py OUT_DIR FILE.lcm...

writes OUT_DIR/dt_pdu_dds.idl (for idlc) and OUT_DIR/dt_pdu_dds_codec.cc (implements
transport/dds_codec.h). Each LCM struct becomes an IDL struct of the same name and members in the same
order (byte -> octet, intN_t -> intN, fixed arrays stay arrays, a variable array T f[n] becomes
sequence<T> f beside the member n). Every PDU type (TOP_LEVEL) gets a last member
`sequence<octet, 128> auth` for bytes that follow the LCM encoding, and the key members listed
for it. Only the subset of LCM the PDUs use is accepted; anything else is an error naming the
file and line.
"""

import re
import sys
from pathlib import Path

# The PDU types: LCM struct -> (dt::PduType enumerator, IDL key members). Features are keyed by
# their ID (origin site and host, feature number) so each feature is one DDS instance.
TOP_LEVEL = {
    "construct_t": ("kConstruct", ["origin", "feature_number"]),
    "update_t": ("kUpdate", ["origin", "feature_number"]),
    "destruct_t": ("kDestruct", ["origin", "feature_number"]),
    "max_feature_t": ("kMaxFeature", []),
    "playback_t": ("kPlayback", []),
    "anti_entropy_t": ("kAntiEntropy", []),
    "vehicle_state_t": ("kVehicleState", ["entity_id"]),
    "earth_move_t": ("kEarthMove", ["origin", "feature_number"]),
    "batch_t": ("kBatch", []),
}
MAX_AUTH_BYTES = 128  # dt::dds_codec::kMaxAuthBytes

# LCM primitive -> (IDL type, C type idlc emits, C++ type lcm-gen emits)
PRIMITIVES = {
    "byte": ("octet", "uint8_t", "uint8_t"),
    "boolean": ("boolean", "bool", "int8_t"),
    "int8_t": ("int8", "int8_t", "int8_t"),
    "int16_t": ("int16", "int16_t", "int16_t"),
    "int32_t": ("int32", "int32_t", "int32_t"),
    "int64_t": ("int64", "int64_t", "int64_t"),
    "float": ("float", "float", "float"),
    "double": ("double", "double", "double"),
}


class Member:
    def __init__(self, type_name, name, dim):
        self.type = type_name
        self.name = name
        self.dim = dim  # None, an int (fixed array) or a member name (variable array)


class Struct:
    def __init__(self, package, name, members, source):
        self.package = package
        self.name = name
        self.members = members
        self.source = source


def fail(where, message):
    sys.exit(f"lcm_to_idl: {where}: {message}")


def parse(path):
    text = Path(path).read_text()
    # Comments out, keeping line numbers.
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    package = None
    structs = []
    pos = 0
    token_re = re.compile(
        r"\s*(?:(package)\s+(\w+)\s*;|(struct)\s+(\w+)\s*\{(.*?)\})", re.S)
    while pos < len(text):
        if not text[pos:].strip():
            break
        m = token_re.match(text, pos)
        if not m:
            line = text.count("\n", 0, pos) + 1
            fail(f"{path}:{line}", "expected 'package NAME;' or 'struct NAME { ... }'")
        if m.group(1):
            package = m.group(2)
        else:
            name, body = m.group(4), m.group(5)
            body_line = text.count("\n", 0, m.start(5)) + 1
            members = []
            for offset, raw in enumerate(body.split("\n")):
                for decl in filter(None, (d.strip() for d in raw.split(";"))):
                    where = f"{path}:{body_line + offset}"
                    dm = re.fullmatch(r"(\w+)\s+(\w+)\s*(?:\[\s*(\w+)\s*\])?", decl)
                    if not dm:
                        fail(where, f"unsupported declaration '{decl}'")
                    type_name, member, dim = dm.groups()
                    if type_name in ("string", "const"):
                        fail(where, f"'{type_name}' is not supported")
                    if dim is not None and dim.isdigit():
                        dim = int(dim)
                    members.append(Member(type_name, member, dim))
            structs.append(Struct(package, name, members, path))
        pos = m.end()
    return structs


def ordered(structs):
    """Dependencies first, so every IDL struct is declared before it is used."""
    by_name = {s.name: s for s in structs}
    done, out = set(), []

    def visit(s, stack):
        if s.name in done:
            return
        if s.name in stack:
            fail(s.source, f"recursive struct {s.name}")
        for m in s.members:
            if m.type not in PRIMITIVES:
                if m.type not in by_name:
                    fail(s.source, f"{s.name}.{m.name}: unknown type {m.type}")
                visit(by_name[m.type], stack | {s.name})
        done.add(s.name)
        out.append(s)

    for s in sorted(structs, key=lambda s: s.name):
        visit(s, set())
    return out


def check(structs):
    names = {s.name for s in structs}
    for top in TOP_LEVEL:
        if top not in names:
            fail("TOP_LEVEL", f"no .lcm file defines {top}")
    for s in structs:
        members = {m.name: m for m in s.members}
        for m in s.members:
            if isinstance(m.dim, str):
                length = members.get(m.dim)
                if length is None or length.type not in ("int8_t", "int16_t", "int32_t", "int64_t"):
                    fail(s.source, f"{s.name}.{m.name}: length {m.dim} is not an integer member")
        for key in TOP_LEVEL.get(s.name, ("", []))[1]:
            if key not in members or members[key].dim is not None:
                fail(s.source, f"{s.name}: key {key} is not a scalar member")
        if s.name in TOP_LEVEL and "auth" in members:
            fail(s.source, f"{s.name}: member 'auth' would clash with the trailer member")


def idl_type(t):
    return PRIMITIVES[t][0] if t in PRIMITIVES else t


def emit_idl(structs):
    lines = [
        "// Generated by transport/idl/lcm_to_idl.py from pdu/lcm/*.lcm: do not edit.",
        "// One IDL struct per LCM struct, members in the same order; every PDU type ends with",
        f"// `auth`, the bytes after the LCM encoding (at most {MAX_AUTH_BYTES}), carried unchanged.",
        "module dtpdu_dds {",
    ]
    for s in structs:
        keys = TOP_LEVEL.get(s.name, ("", []))[1]
        lines.append("  @final")
        lines.append(f"  struct {s.name} {{")
        for m in s.members:
            key = "@key " if m.name in keys else ""
            if m.dim is None:
                lines.append(f"    {key}{idl_type(m.type)} {m.name};")
            elif isinstance(m.dim, int):
                lines.append(f"    {key}{idl_type(m.type)} {m.name}[{m.dim}];")
            else:
                lines.append(f"    sequence<{idl_type(m.type)}> {m.name};  // length: {m.dim}")
        if s.name in TOP_LEVEL:
            lines.append(f"    sequence<octet, {MAX_AUTH_BYTES}> auth;")
        lines.append("  };")
    lines.append("};")
    return "\n".join(lines) + "\n"


def c_name(s):
    return f"dtpdu_dds_{s}"


def emit_codec(structs):
    by_name = {s.name: s for s in structs}
    nested_seq_types = sorted({m.type for s in structs for m in s.members
                               if isinstance(m.dim, str) and m.type not in PRIMITIVES})
    prim_seq_types = sorted({m.type for s in structs for m in s.members
                             if isinstance(m.dim, str) and m.type in PRIMITIVES})
    out = [
        "// Generated by transport/idl/lcm_to_idl.py from pdu/lcm/*.lcm: do not edit.",
        "// Converts every PDU between its LCM type and its IDL type (transport/dds_codec.h).",
        '#include "transport/dds_codec.h"',
        "",
        "#include <cstring>",
        "#include <deque>",
        "#include <vector>",
        "",
        "#include <fmt/format.h>",
        "",
        '#include <dt_pdu_dds.h>',
    ]
    for s in structs:
        out.append(f'#include <{s.package}/{s.name}.hpp>')
    out += ["", "namespace dt::dds_codec {", "namespace {", "",
            "// Buffers for the sequences of a sample being written, kept between writes so a",
            "// write allocates nothing once they have grown.",
            "template <typename T>",
            "struct Pool {",
            "  std::deque<std::vector<T>> buffers;  // grows without moving what it holds",
            "  size_t used = 0;",
            "  std::vector<T>& Next(size_t n) {",
            "    if (used == buffers.size()) buffers.emplace_back();",
            "    std::vector<T>& v = buffers[used++];",
            "    v.resize(n);",
            "    return v;",
            "  }",
            "};",
            "",
            "struct Arena {"]
    for t in nested_seq_types:
        out.append(f"  Pool<{c_name(t)}> {t}_pool;")
    for t in prim_seq_types:
        out.append(f"  Pool<{PRIMITIVES[t][1]}> {t}_pool;")  # a member named int64_t would shadow it
    out.append("  void Reset() {")
    for t in nested_seq_types + prim_seq_types:
        out.append(f"    {t}_pool.used = 0;")
    out += ["  }", "};", ""]
    # Declarations first: nested structs refer to each other in dependency order anyway.
    for s in structs:
        lcm = f"{s.package}::{s.name}"
        idl = c_name(s.name)
        out.append(f"[[maybe_unused]] void ToIdl(const {lcm}& in, {idl}& out, Arena& arena) {{")
        out.append("  (void)arena;")
        for m in s.members:
            if m.dim is None:
                out.append(conv_to(m, f"in.{m.name}", f"out.{m.name}"))
            elif isinstance(m.dim, int):
                out.append(f"  for (size_t i = 0; i < {m.dim}; ++i) {{")
                out.append("  " + conv_to(m, f"in.{m.name}[i]", f"out.{m.name}[i]"))
                out.append("  }")
            else:
                store = m.type
                elem = c_name(m.type) if m.type not in PRIMITIVES else PRIMITIVES[m.type][1]
                out.append("  {")
                out.append(f"    std::vector<{elem}>& v = arena.{store}_pool.Next(in.{m.name}.size());")
                out.append("    for (size_t i = 0; i < v.size(); ++i) {")
                out.append("    " + conv_to(m, f"in.{m.name}[i]", "v[i]"))
                out.append("    }")
                out.append(f"    out.{m.name}._maximum = static_cast<uint32_t>(v.size());")
                out.append(f"    out.{m.name}._length = static_cast<uint32_t>(v.size());")
                out.append(f"    out.{m.name}._buffer = v.data();")
                out.append(f"    out.{m.name}._release = false;")
                out.append("  }")
        out.append("}")
        out.append("")
        out.append(f"[[maybe_unused]] bool FromIdl(const {idl}& in, {lcm}& out) {{")
        for m in s.members:
            if m.dim is None:
                out.append(conv_from(m, f"in.{m.name}", f"out.{m.name}"))
            elif isinstance(m.dim, int):
                out.append(f"  for (size_t i = 0; i < {m.dim}; ++i) {{")
                out.append("  " + conv_from(m, f"in.{m.name}[i]", f"out.{m.name}[i]"))
                out.append("  }")
            else:
                out.append(f"  // LCM encodes {m.dim} elements of {m.name}: they must agree.")
                out.append(f"  if (in.{m.dim} < 0 || static_cast<uint64_t>(in.{m.dim}) != in.{m.name}._length) return false;")
                out.append(f"  out.{m.name}.resize(in.{m.name}._length);")
                out.append(f"  for (size_t i = 0; i < in.{m.name}._length; ++i) {{")
                out.append("  " + conv_from(m, f"in.{m.name}._buffer[i]", f"out.{m.name}[i]"))
                out.append("  }")
        out.append("  return true;")
        out.append("}")
        out.append("")
    # `Lcm pdu{}`: value-initialised, or GCC -O2 -Werror (the ci preset) suspects fixed arrays
    # of read before LCM's decode wrote them.
    out += [
        "template <typename Lcm, typename Idl>",
        "Status WriteAs(dds_entity_t writer, std::string_view lcm_name, std::span<const uint8_t> bytes) {",
        "  Lcm pdu{};",
        "  const int used = pdu.decode(bytes.data(), 0, static_cast<int>(bytes.size()));",
        "  if (used < 0) {",
        "    return Error{fmt::format(\"{} bytes are not an LCM-encoded {} (wrong fingerprint or truncated)\",",
        "                             bytes.size(), lcm_name)};",
        "  }",
        "  const size_t trailer = bytes.size() - static_cast<size_t>(used);",
        "  if (trailer > kMaxAuthBytes) {",
        "    return Error{fmt::format(\"{}: {} bytes follow the PDU, more than the {} an IDL sample carries\",",
        "                             lcm_name, trailer, kMaxAuthBytes)};",
        "  }",
        "  Idl sample{};",
        "  // One transport thread writes at a time (Transport is not thread-safe); thread_local",
        "  // keeps transports on different threads apart.",
        "  static thread_local Arena arena;",
        "  arena.Reset();",
        "  ToIdl(pdu, sample, arena);",
        "  sample.auth._maximum = static_cast<uint32_t>(trailer);",
        "  sample.auth._length = static_cast<uint32_t>(trailer);",
        "  // Only read by dds_write.",
        "  sample.auth._buffer = const_cast<uint8_t*>(bytes.data()) + used;",
        "  sample.auth._release = false;",
        "  const dds_return_t rc = dds_write(writer, &sample);",
        "  if (rc != DDS_RETCODE_OK) return Error{dds_strretcode(rc)};",
        "  return Status::Ok();",
        "}",
        "",
        "template <typename Lcm, typename Idl>",
        "bool ReadAs(const void* sample, std::vector<uint8_t>& bytes) {",
        "  const Idl& s = *static_cast<const Idl*>(sample);",
        "  Lcm pdu{};",
        "  if (!FromIdl(s, pdu)) return false;",
        "  const int size = pdu.getEncodedSize();",
        "  bytes.resize(static_cast<size_t>(size) + s.auth._length);",
        "  if (pdu.encode(bytes.data(), 0, size) != size) return false;",
        "  if (s.auth._length > 0) std::memcpy(bytes.data() + size, s.auth._buffer, s.auth._length);",
        "  return true;",
        "}",
        "",
        "}  // namespace",
        "",
        "const dds_topic_descriptor_t* Descriptor(PduType type) {",
        "  switch (type) {",
    ]
    for name, (enum, _) in TOP_LEVEL.items():
        out.append(f"    case PduType::{enum}:")
        out.append(f"      return &{c_name(name)}_desc;")
    out += ["  }", "  std::abort();  // every PduType is listed", "}", "",
            "Status Write(PduType type, dds_entity_t writer, std::span<const uint8_t> bytes) {",
            "  switch (type) {"]
    for name, (enum, _) in TOP_LEVEL.items():
        s = by_name[name]
        out.append(f"    case PduType::{enum}:")
        out.append(f"      return WriteAs<{s.package}::{name}, {c_name(name)}>(writer, \"{name}\", bytes);")
    out += ["  }", "  std::abort();  // every PduType is listed", "}", "",
            "bool Read(PduType type, const void* sample, std::vector<uint8_t>& bytes) {",
            "  switch (type) {"]
    for name, (enum, _) in TOP_LEVEL.items():
        s = by_name[name]
        out.append(f"    case PduType::{enum}:")
        out.append(f"      return ReadAs<{s.package}::{name}, {c_name(name)}>(sample, bytes);")
    out += ["  }", "  std::abort();  // every PduType is listed", "}", "",
            "}  // namespace dt::dds_codec", ""]
    return "\n".join(out)


def conv_to(m, src, dst):
    if m.type in PRIMITIVES:
        if m.type == "boolean":
            return f"  {dst} = {src} != 0;"
        return f"  {dst} = static_cast<{PRIMITIVES[m.type][1]}>({src});"
    return f"  ToIdl({src}, {dst}, arena);"


def conv_from(m, src, dst):
    if m.type in PRIMITIVES:
        if m.type == "boolean":
            return f"  {dst} = {src} ? 1 : 0;"
        return f"  {dst} = static_cast<{PRIMITIVES[m.type][2]}>({src});"
    return f"  if (!FromIdl({src}, {dst})) return false;"


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: lcm_to_idl.py OUT_DIR FILE.lcm...")
    out_dir = Path(sys.argv[1])
    structs = []
    for path in sys.argv[2:]:
        structs += parse(path)
    structs = ordered(structs)
    check(structs)
    out_dir.mkdir(parents=True, exist_ok=True)
    for name, text in (("dt_pdu_dds.idl", emit_idl(structs)),
                       ("dt_pdu_dds_codec.cc", emit_codec(structs))):
        target = out_dir / name
        # Unchanged output keeps its timestamp, so idlc and the compiler do not run again.
        if not target.exists() or target.read_text() != text:
            target.write_text(text)


if __name__ == "__main__":
    main()
