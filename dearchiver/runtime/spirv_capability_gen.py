#!/usr/bin/env python3
"""Build-time tool: turns the Vulkan registry's table of SPIR-V capabilities (vk.xml's
<spirvcapabilities>, Debian's libvulkan-dev) into the rows enabled_features.cpp checks each shader
module's OpCapability against: for every capability Vulkan allows, the ways to allow it (a core
version, a feature of a feature structure, a device extension, or a device property). Capability
numbers come from SPIR-V's grammar (spirv-headers). Feature structures that vulkan_core.h does not
declare (platform and provisional extensions) are left out, with the capabilities only they allow.

It also lists the device extensions that allow capabilities, with their feature structures and the
device extensions they require, for a device meant to run any archive (statepack verify).

Usage: spirv_capability_gen.py <vk.xml> <spirv.core.grammar.json> <vulkan_core.h> <output.inc>"""
import json
import re
import sys
import xml.etree.ElementTree as ET


# Extensions a device must not enable together with features the others bring
# (VUID-VkDeviceCreateInfo-fragmentDensityMap-04481: no density map with fragment shading rates).
CONFLICTING = {"VK_EXT_fragment_density_map"}


def version_macro(name):
    m = re.fullmatch(r"VK_(?:API_)?VERSION_(\d+)_(\d+)", name)
    return f"VK_API_VERSION_{m.group(1)}_{m.group(2)}" if m else None


def main(registry_path, grammar_path, header_path, target):
    registry = ET.parse(registry_path).getroot()
    with open(grammar_path, encoding="utf-8") as f:
        grammar = json.load(f)
    with open(header_path, encoding="utf-8") as f:
        header = f.read()
    numbers = {}
    for kind in grammar["operand_kinds"]:
        if kind["kind"] == "Capability":
            for e in kind["enumerants"]:
                numbers.setdefault(e["enumerant"], int(e["value"]))
    s_types = {}
    for t in registry.iter("type"):
        if t.get("category") != "struct":
            continue
        for m in t.findall("member"):
            if m.findtext("name") == "sType" and m.get("values"):
                s_types[t.get("name")] = m.get("values").split(",")[0]

    # Feature structures by the extension that brings them (aliases resolved), for features that moved
    # into VkPhysicalDeviceVulkan1xFeatures: vk.xml names the core structure, and says in `requires`
    # which extension's structure holds the same member on a device without that core version.
    aliases = {t.get("name"): t.get("alias") for t in registry.iter("type") if t.get("alias")}
    members = {}
    extends_features = set()
    for t in registry.iter("type"):
        if t.get("category") == "struct" and not t.get("alias"):
            members[t.get("name")] = {m.findtext("name") for m in t.findall("member")}
            if "VkPhysicalDeviceFeatures2" in (t.get("structextends") or "").split(","):
                extends_features.add(t.get("name"))
    structs_of_extension = {}
    for ext in registry.find("extensions").findall("extension"):
        for req in ext.findall("require"):
            for ty in req.findall("type"):
                name = aliases.get(ty.get("name"), ty.get("name"))
                found = structs_of_extension.setdefault(ext.get("name"), [])
                if name in extends_features and name not in found:
                    found.append(name)

    def declared(struct):
        return re.search(r"typedef struct " + re.escape(struct) + r" \{", header) is not None

    structs = {}  # feature and property structures the rows read: name -> sType
    rows = []
    for cap in registry.find("spirvcapabilities").findall("spirvcapability"):
        name = cap.get("name")
        if name not in numbers:
            continue  # newer than this SPIR-V grammar: no module here can declare it
        for e in cap.findall("enable"):
            a = e.attrib
            if "version" in a:
                rows.append((name, "version", version_macro(a["version"]), "0", "0", '""', '""', "0"))
            elif "struct" in a:
                struct, feature = a["struct"], a["feature"]
                if struct == "VkPhysicalDeviceFeatures":
                    offset = f"offsetof(VkPhysicalDeviceFeatures2, features) + offsetof(VkPhysicalDeviceFeatures, {feature})"
                    s_type = "VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2"
                    structs["VkPhysicalDeviceFeatures2"] = s_type
                elif declared(struct) and struct in s_types:
                    offset = f"offsetof({struct}, {feature})"
                    s_type = s_types[struct]
                    structs[struct] = s_type
                else:
                    continue
                rows.append((name, "feature", "0", s_type, offset, f'"{struct}::{feature}"', '""', "0"))
                for ext in a.get("requires", "").split(","):
                    for other in structs_of_extension.get(ext, []):
                        if other != struct and feature in members.get(other, ()) and declared(other):
                            structs[other] = s_types[other]
                            rows.append((name, "feature", "0", s_types[other], f"offsetof({other}, {feature})",
                                         f'"{other}::{feature}"', '""', "0"))
            elif "extension" in a:
                rows.append((name, "extension", "0", "0", "0", '""', f'"{a["extension"]}"', "0"))
            elif "property" in a:
                struct, member, value = a["property"], a["member"], a["value"]
                if not declared(struct) or struct not in s_types:
                    continue
                structs[struct] = s_types[struct]
                bits = "1" if value == "VK_TRUE" else value
                rows.append((name, "property", "0", s_types[struct], f"offsetof({struct}, {member})",
                             f'"{struct}::{member} with {value}"', '""', bits))
    # The device extensions that allow a capability (directly, or by bringing a feature structure that
    # does), with their feature structures and the device extensions they need in turn: what a device
    # that should run any archive (statepack verify) enables when it has them.
    device_extensions = {}
    for ext in registry.find("extensions").findall("extension"):
        if ext.get("type") == "device" and ext.get("supported", "").split(",").count("vulkan") and \
                not ext.get("platform") and not ext.get("provisional") and not ext.get("promotedto") and \
                not ext.get("deprecatedby") and ext.get("name").split("_")[1] in ("KHR", "EXT") and \
                ext.get("name") not in CONFLICTING:
            device_extensions[ext.get("name")] = ext
    wanted = set()
    for cap in registry.find("spirvcapabilities").findall("spirvcapability"):
        if cap.get("name") not in numbers:
            continue
        for e in cap.findall("enable"):
            if "extension" in e.attrib:
                wanted.add(e.get("extension"))
            for req in e.get("requires", "").split(","):
                wanted.add(req)
    wanted &= set(device_extensions)
    pending = list(wanted)
    while pending:
        for dep in (device_extensions[pending.pop()].get("requires") or "").split(","):
            if dep in device_extensions and dep not in wanted:
                wanted.add(dep)
                pending.append(dep)
    extension_rows, dependency_rows = [], []
    for name in sorted(wanted):
        found = [st for st in structs_of_extension.get(name, []) if declared(st) and st in s_types]
        for st in found:
            structs[st] = s_types[st]
            extension_rows.append((name, s_types[st], f"sizeof({st})"))
        if not found:
            extension_rows.append((name, "0", "0"))
        for dep in (device_extensions[name].get("requires") or "").split(","):
            if dep in wanted:
                dependency_rows.append((name, dep))
    with open(target, "w", encoding="utf-8") as out:
        out.write("// Generated by dearchiver/runtime/spirv_capability_gen.py from vk.xml; do not edit.\n")
        out.write("constexpr StructSize kCapabilityStructs[] = {\n")
        for struct, s_type in sorted(structs.items()):
            out.write(f"    {{{s_type}, sizeof({struct})}},\n")
        out.write("};\n")
        # The rows' words as offsets into one string (kCapabilityText), each string once, not as pointers:
        # a pointer costs a position-independent program a relocation (24 bytes) beside its own 8.
        text, at = [""], {"": 0}
        def offset_of(quoted):
            word = quoted.strip('"')
            if word not in at:
                last = text[-1]
                at[word] = at[last] + len(last) + 1  # after the last word and its NUL
                text.append(word)
            return at[word]
        out.write("constexpr CapabilityEnable kCapabilityEnables[] = {\n")
        for name, kind, version, s_type, offset, feature, extension, bits in rows:
            # "Struct::member": the structure's name and the member's apart, each kept once.
            struct, _, member = feature.strip('"').partition("::")
            out.write(f'    {{{numbers[name]}, {offset_of(name)}, EnableKind::{kind}, {version}, '
                      f"VkStructureType({s_type}), uint32_t({offset}), {offset_of(struct)}, {offset_of(member)}, "
                      f"{offset_of(extension)}, uint32_t({bits})}},\n")
        out.write("};\n")
        if at[text[-1]] + len(text[-1]) + 1 > 0xFFFF:
            raise SystemExit("spirv_capability_gen: the rows' text exceeds 64 KiB: widen CapabilityEnable's offsets")
        out.write("constexpr char kCapabilityText[] =\n" + "".join(f'    "{t}\\0"\n' for t in text) + ";\n")
        out.write("constexpr ExtensionStruct kCapabilityExtensions[] = {\n")
        for name, s_type, size in extension_rows:
            out.write(f'    {{"{name}", VkStructureType({s_type}), {size}}},\n')
        out.write("};\n")
        out.write("constexpr ExtensionDependency kCapabilityExtensionDependencies[] = {\n")
        for name, dep in dependency_rows:
            out.write(f'    {{"{name}", "{dep}"}},\n')
        out.write("};\n")


if __name__ == "__main__":
    if len(sys.argv) != 5:
        raise SystemExit(__doc__)
    main(*sys.argv[1:])
