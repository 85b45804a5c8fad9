#include "specialization.hpp"

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include "notation/enum_tables.hpp"
#include "support/suggest.hpp"

namespace statepack::packager {
namespace {

using Kind = ReflectedConstant::Kind;

const char* kind_name(Kind kind) {
  switch (kind) {
    case Kind::boolean:
      return "bool";
    case Kind::int32:
      return "int";
    case Kind::uint32:
      return "uint";
    case Kind::float32:
      return "float";
    case Kind::int64:
      return "int64_t";
    case Kind::uint64:
      return "uint64_t";
    case Kind::float64:
      return "double";
    case Kind::other:
      break;
  }
  return "a type specialization cannot set";
}

// The value's bytes for a constant of `kind`, or nullopt when it does not fit.
std::optional<uint64_t> encode_value(const ScalarValue& v, Kind kind) {
  using VK = ScalarValue::Kind;
  const bool integral = v.kind == VK::signed_integer || v.kind == VK::unsigned_integer;
  // As a signed 128-bit-free range check: unsigned values above INT64_MAX only fit unsigned kinds.
  auto fits = [&](long double low, long double high) {
    long double x =
        v.kind == VK::unsigned_integer ? (long double)v.unsigned_integer : (long double)v.signed_integer;
    return x >= low && x <= high;
  };
  switch (kind) {
    case Kind::boolean:
      if (v.kind != VK::boolean) return std::nullopt;
      return v.boolean ? 1u : 0u;  // VkBool32
    case Kind::int32:
      if (!integral || !fits(INT32_MIN, INT32_MAX)) return std::nullopt;
      return uint32_t(
          int32_t(v.kind == VK::unsigned_integer ? int64_t(v.unsigned_integer) : v.signed_integer));
    case Kind::uint32:
      if (!integral || !fits(0, UINT32_MAX)) return std::nullopt;
      return v.kind == VK::unsigned_integer ? v.unsigned_integer : uint64_t(v.signed_integer);
    case Kind::int64:
      if (!integral || !fits((long double)INT64_MIN, (long double)INT64_MAX)) return std::nullopt;
      return v.kind == VK::unsigned_integer ? v.unsigned_integer : uint64_t(v.signed_integer);
    case Kind::uint64:
      if (!integral || (v.kind == VK::signed_integer && v.signed_integer < 0)) return std::nullopt;
      return v.kind == VK::unsigned_integer ? v.unsigned_integer : uint64_t(v.signed_integer);
    case Kind::float32:
    case Kind::float64: {
      if (v.kind == VK::boolean || v.kind == VK::other) return std::nullopt;
      double d = v.kind == VK::floating           ? v.floating
                 : v.kind == VK::unsigned_integer ? double(v.unsigned_integer)
                                                  : double(v.signed_integer);
      if (!std::isfinite(d)) return std::nullopt;
      if (kind == Kind::float64) return std::bit_cast<uint64_t>(d);
      if (std::fabs(d) > double(FLT_MAX)) return std::nullopt;
      return std::bit_cast<uint32_t>(float(d));
    }
    case Kind::other:
      break;
  }
  return std::nullopt;
}

// The notation's name of a single stage (kShaderTypes is the table the reader uses).
std::string stage_text(uint32_t stage) {
  for (const auto& [name, value] : kShaderTypes)
    if (value == stage) return std::string(name);
  return "stage " + std::to_string(stage);
}

}  // namespace

bool resolve_constants(const PipelineDesc& p, const std::vector<StageInput>& stages,
                       std::vector<format::SpecConstant>& out, Diagnostics& diag) {
  bool ok = true;
  auto fail = [&](const SpecConstantDesc& k, const std::string& message) {
    diag.error(k.where, "pipeline '" + p.name + "': specialization constant '" + k.name + "': " + message);
    ok = false;
  };
  // What Diligent's Vulkan backend skips silently ("the user may supply a superset"): a warning, and the
  // constant is left out for that stage.
  auto skip = [&](const SpecConstantDesc& k, const std::string& message) {
    diag.warning(k.where, "pipeline '" + p.name + "': specialization constant '" + k.name + "': " + message +
                              "; it is left out, as in Diligent");
  };
  for (const SpecConstantDesc& k : p.constants) {
    std::vector<std::string> all_names;
    bool found_any = false;
    for (const StageInput& stage : stages) {
      const uint32_t bit = stage.desc->stage;
      const bool named = k.stages != 0 && (k.stages & bit);
      if (k.stages != 0 && !named) continue;
      const ReflectedConstant* declared = nullptr;
      for (const ReflectedConstant& r : stage.reflection->constants) {
        if (!r.name.empty()) all_names.push_back(r.name);
        if (r.name == k.name) declared = &r;
      }
      if (!declared) {
        if (named)
          skip(k, "shader '" + stage.desc->name + "' (" + stage_text(bit) + ") declares no such constant" +
                      detail::did_you_mean(k.name, all_names));
        continue;
      }
      found_any = true;
      if (k.size && *k.size < declared->size) {  // a larger Size is fine: Diligent uses the declared one
        fail(k, "'Size' is " + std::to_string(*k.size) + ", but shader '" + stage.desc->name +
                    "' declares a " + kind_name(declared->kind) + " of " + std::to_string(declared->size) +
                    " bytes");
        continue;
      }
      auto bytes = encode_value(k.value, declared->kind);
      if (!bytes) {
        fail(k, "the value " + k.value.text + " does not fit its type, " + kind_name(declared->kind) +
                    ", in shader '" + stage.desc->name + "'");
        continue;
      }
      out.push_back({k.name, bit, declared->constant_id, declared->size, *bytes});
    }
    if (k.stages != 0) {
      uint32_t present = 0;
      for (const StageInput& stage : stages) present |= stage.desc->stage;
      for (uint32_t bit = 1; bit <= 0x20; bit <<= 1)
        if ((k.stages & bit) && !(present & bit))
          skip(k, "'ShaderStages' names " + stage_text(bit) + ", but the pipeline has no such shader");
    } else if (!found_any) {
      skip(k, "no shader of the pipeline declares it" + detail::did_you_mean(k.name, all_names));
    }
  }
  return ok;
}

}  // namespace statepack::packager
