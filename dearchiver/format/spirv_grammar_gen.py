#!/usr/bin/env python3
"""Build-time tool: turns SPIR-V's machine-readable grammar (spirv.core.grammar.json from Debian's
spirv-headers) into the operand tables spirv_structure.cpp reads (spirv_grammar.hpp gives their types),
so the load-time structure check knows every instruction's operands without linking SPIRV-Tools into
the runtime. Python's json module, not a C++ JSON library: a dearchiver-only build needs none.

Usage: spirv_grammar_gen.py <spirv.core.grammar.json> <output.inc>"""
import json
import sys

KINDS = {
    "IdResultType": "result_type", "IdResult": "result",
    "IdRef": "id", "IdScope": "id", "IdMemorySemantics": "id",
    "LiteralInteger": "literal", "LiteralExtInstInteger": "literal",
    "LiteralString": "string", "LiteralContextDependentNumber": "context_number",
    "LiteralSpecConstantOpInteger": "spec_opcode",
    "PairLiteralIntegerIdRef": "pair_literal_id", "PairIdRefLiteralInteger": "pair_id_literal",
    "PairIdRefIdRef": "pair_id_id",
}
QUANTIFIERS = {"": "one", "?": "optional", "*": "many"}


def value_of(v):
    return int(v, 0) if isinstance(v, str) else v


def main(source, target):
    with open(source, encoding="utf-8") as f:
        grammar = json.load(f)
    kinds = {k["kind"]: k for k in grammar["operand_kinds"]}
    enums = [k["kind"] for k in grammar["operand_kinds"] if k["category"] in ("ValueEnum", "BitEnum")]
    enum_index = {name: i for i, name in enumerate(enums)}
    operands, enumerants, enum_rows, instructions = [], [], [], []

    def row(o, names_type=False):
        kind = o["kind"]
        category = kinds.get(kind, {}).get("category")
        k = KINDS.get(kind) or {"ValueEnum": "value_enum", "BitEnum": "bit_enum"}.get(category)
        if k is None:
            raise SystemExit(f"spirv_grammar_gen: operand kind {kind} is unknown to this generator")
        if enum_index.get(kind, 0) > 0xFF:
            raise SystemExit("spirv_grammar_gen: more than 256 enum kinds: widen Operand::enum_kind")
        return (f"{{Kind::{k}, Quantifier::{QUANTIFIERS[o.get('quantifier', '')]}, "
                f"{'true' if names_type else 'false'}, {enum_index.get(kind, 0)}}}")

    # Where a list of operands starts in kOperands: where the same run already is (most instructions
    # share theirs with others: "result type, result, id, id"), else appended.
    def place(run):
        for start in range(len(operands) - len(run) + 1):
            if operands[start:start + len(run)] == run:
                return start
        operands.extend(run)
        return len(operands) - len(run)

    def has_parameters(kind):
        return any("parameters" in e for e in kinds[kind].get("enumerants", []))

    # Enumerants with parameters only (the others are one word); aliases share a value, the first
    # stands for them.
    for name in enums:
        first, seen, carrying = len(enumerants), set(), {}
        for e in kinds[name]["enumerants"]:
            value = value_of(e["value"])
            if value not in seen:
                seen.add(value)
                if "parameters" in e:
                    carrying[value] = e["parameters"]
        for value in sorted(carrying):
            for p in carrying[value]:
                if p["kind"] in enum_index and has_parameters(p["kind"]):
                    raise SystemExit(f"spirv_grammar_gen: parameter {p['kind']} has parameters of its own")
            parameters = [row(p) for p in carrying[value]]
            enumerants.append(f"{{{value}u, {place(parameters)}, {len(parameters)}}}")
        bits = "true" if kinds[name]["category"] == "BitEnum" else "false"
        enum_rows.append(f'{{{bits}, {first}, {len(enumerants) - first}}}')

    by_opcode, names, names_size = {}, [""], 1  # offset 0: no name
    for i in grammar["instructions"]:
        by_opcode.setdefault(i["opcode"], i)  # the first of aliases sharing an opcode
    for opcode in sorted(by_opcode):
        i = by_opcode[opcode]
        name = i["opname"]
        is_type = name.startswith("OpType")
        defines = any(o["kind"] == "IdResult" for o in i.get("operands", []))
        own = [row(o, is_type and o["kind"] == "IdRef" and "type" in o.get("name", "").lower())
               for o in i.get("operands", [])]
        first = place(own)
        flags = ["0"]
        if defines and is_type:
            flags.append("kDefinesType")
        if defines and i["class"] == "Constant-Creation":
            flags.append("kDefinesConstant")
        # Debug names, decorations, entry points and execution modes come before what they name.
        if i["class"] in ("Debug", "Annotation", "Mode-Setting"):
            flags.append("kMayReferenceForward")
        # Names as offsets into one string, not pointers: a pointer per row costs the program a
        # relocation (24 bytes in a position-independent program) beside its own 8.
        # Intel's instructions (OpenCL and FPGA work, more names than all the others) go unnamed:
        # a message about one says its opcode.
        if name.endswith("INTEL"):
            instructions.append(f'{{{opcode}, {first}, {len(own)}, {" | ".join(flags)}, 0}}')
            continue
        instructions.append(f'{{{opcode}, {first}, {len(own)}, {" | ".join(flags)}, {names_size}}}')
        names.append(name)
        names_size += len(name) + 1  # with its NUL
        if names_size > 0xFFFF:
            raise SystemExit("spirv_grammar_gen: instruction names exceed 64 KiB: widen Instruction::name")

    version = f"{grammar['major_version']}.{grammar['minor_version']} revision {grammar['revision']}"
    def table(decl, rows):
        return f"inline constexpr {decl}[] = {{\n" + "".join(f"    {r},\n" for r in rows) + "};\n"
    text = (f"// Generated by spirv_grammar_gen.py from {source} (SPIR-V {version}). Do not edit.\n"
            f'inline constexpr char kGrammarVersion[] = "{version}";\n'
            + table("Operand kOperands", operands) + table("Enumerant kEnumerants", enumerants)
            + table("EnumKind kEnumKinds", enum_rows) + table("Instruction kInstructions", instructions)
            + "inline constexpr char kInstructionNames[] =\n" + "".join(f'    "{n}\\0"\n' for n in names) + ";\n")
    with open(target, "w", encoding="utf-8") as f:
        f.write(text)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit("usage: spirv_grammar_gen.py <spirv.core.grammar.json> <output.inc>")
    main(sys.argv[1], sys.argv[2])
