// Variants files: the patched pipelines an application made, each by its pipeline's name and the
// fields of PatchableState its callback changed, so that a build or install step can create exactly
// those again (`statepack verify ARCHIVE --variants FILE --cache OUT`) and warm a pipeline cache.
// docs/variants.md is the reference; this is its reader and writer:
//
// | key (top level)        | value                                                                  |
// |------------------------|------------------------------------------------------------------------|
// | `statepack_variants`   | 1, this layout's version (a reader refuses a newer one)                |
// | `variants`             | array of variants, in the order the application first made them        |
//
// | key (a variant)        | value                                                                  |
// |------------------------|------------------------------------------------------------------------|
// | `pipeline`             | the pipeline's name in the archive                                     |
// | `kind`                 | `"graphics"` or `"compute"`                                            |
// | `state`                | object: the fields the callback changed (kFields' keys, Vulkan's enum   |
// |                        | names), `dynamic_states` (the whole list) and `constants` (name: the    |
// |                        | value's bits as an unsigned integer); a compute variant has constants   |
//
// Only what changed is recorded, so a variant still applies when the archive's other state changes.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include "api_guard.hpp"

#include "dearchiver_state.hpp"
#include "patchable_state.hpp"
#include "support/failure.hpp"
#include "support/file_io.hpp"
#include "support/printable.hpp"
#include "support/suggest.hpp"
#include "vk_enum_names.hpp"

namespace statepack {
using namespace detail;

namespace {

using Json = nlohmann::ordered_json;
constexpr int kVariantsVersion = 1;
constexpr uint64_t kMaxVariantsFileBytes = uint64_t(64) << 20;
constexpr size_t kMaxDepth = 16;  // the layout needs 4 levels; deeper is not a variants file

const char* type_name(VkFormat) {
  return "VkFormat";
}
const char* type_name(VkBlendFactor) {
  return "VkBlendFactor";
}
const char* type_name(VkBlendOp) {
  return "VkBlendOp";
}
const char* type_name(VkCompareOp) {
  return "VkCompareOp";
}
const char* type_name(VkStencilOp) {
  return "VkStencilOp";
}
const char* type_name(VkPolygonMode) {
  return "VkPolygonMode";
}
const char* type_name(VkFrontFace) {
  return "VkFrontFace";
}
const char* type_name(VkSampleCountFlagBits) {
  return "VkSampleCountFlagBits";
}
const char* type_name(VkDynamicState) {
  return "VkDynamicState";
}

template <class T>
Json to_json(const T& value) {
  if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, uint32_t>)
    return value;
  else if constexpr (std::is_same_v<T, float>)
    return double(value);
  else
    return vk_name(
        value);  // a value without a name is written as "VkFormat 123", which reads back as an error
}

// Sets `out` from `j`; "" when it could, else what is wrong with the value.
template <class T>
std::string from_json(const Json& j, T& out) {
  if constexpr (std::is_same_v<T, bool>) {
    if (!j.is_boolean()) return "expected true or false";
    out = j.get<bool>();
  } else if constexpr (std::is_same_v<T, uint32_t>) {
    if (!j.is_number_integer() || (!j.is_number_unsigned() && j.get<int64_t>() < 0) ||
        j.get<uint64_t>() > std::numeric_limits<uint32_t>::max())
      return "expected an unsigned 32-bit integer";
    out = j.get<uint32_t>();
  } else if constexpr (std::is_same_v<T, float>) {
    if (!j.is_number() || !std::isfinite(j.get<double>()) ||
        std::fabs(j.get<double>()) > double(std::numeric_limits<float>::max()))
      return "expected a finite number a float can hold";
    out = float(j.get<double>());
  } else {
    if (!j.is_string())
      return std::string("expected a ") + type_name(out) + " name, such as " +
             vk_name(std::is_same_v<T, VkSampleCountFlagBits> ? T(1) : T{});
    const std::string& name = j.get_ref<const std::string&>();
    if (!vk_value(name, out))
      return "'" + printable(name) + "' is not a " + type_name(out) + " name" +
             did_you_mean(name, vk_names(out));
  }
  return "";
}

// One field of PatchableState a variants file may hold, read and written the same way.
struct Field {
  std::string key;
  std::function<bool(const PatchableState&, const PatchableState&)> differs;
  std::function<Json(const PatchableState&)> write;
  std::function<std::string(const Json&, PatchableState&)> read;
};

template <class Access>
Field field(std::string key, Access access) {
  return {std::move(key),
          [access](const PatchableState& a, const PatchableState& b) {
            const auto &x = access(a), &y = access(b);
            return std::memcmp(&x, &y, sizeof x) != 0;  // floats by their bits: -0 and NaN are values too
          },
          [access](const PatchableState& s) { return to_json(access(s)); },
          [access](const Json& j, PatchableState& s) { return from_json(j, access(s)); }};
}

void add_stencil_fields(std::vector<Field>& f, const std::string& side,
                        VkStencilOpState DepthStencilState::*op) {
  const std::string p = "depth_stencil." + side + ".";
  f.push_back(field(
      p + "fail_op", [op](auto& s) -> auto& { return (s.depth_stencil.*op).failOp; }));
  f.push_back(field(
      p + "pass_op", [op](auto& s) -> auto& { return (s.depth_stencil.*op).passOp; }));
  f.push_back(field(
      p + "depth_fail_op", [op](auto& s) -> auto& { return (s.depth_stencil.*op).depthFailOp; }));
  f.push_back(field(
      p + "compare_op", [op](auto& s) -> auto& { return (s.depth_stencil.*op).compareOp; }));
  f.push_back(field(
      p + "compare_mask", [op](auto& s) -> auto& { return (s.depth_stencil.*op).compareMask; }));
  f.push_back(field(
      p + "write_mask", [op](auto& s) -> auto& { return (s.depth_stencil.*op).writeMask; }));
  f.push_back(field(
      p + "reference", [op](auto& s) -> auto& { return (s.depth_stencil.*op).reference; }));
}

// Every field but dynamic_states and constants, in PatchableState's order.
const std::vector<Field>& fields() {
  static const std::vector<Field> table = [] {
    std::vector<Field> f;
    f.push_back(field(
        "color_count", [](auto& s) -> auto& { return s.color_count; }));
    for (uint32_t i = 0; i < PatchableState{}.color_formats.size(); ++i)
      f.push_back(field(
          "color_formats." + std::to_string(i), [i](auto& s) -> auto& { return s.color_formats[i]; }));
    f.push_back(field(
        "depth_stencil_format", [](auto& s) -> auto& { return s.depth_stencil_format; }));
    f.push_back(field(
        "samples", [](auto& s) -> auto& { return s.samples; }));
    for (uint32_t i = 0; i < PatchableState{}.blend.size(); ++i) {
      const std::string p = "blend." + std::to_string(i) + ".";
      f.push_back(field(
          p + "enable", [i](auto& s) -> auto& { return s.blend[i].enable; }));
      f.push_back(field(
          p + "src_color", [i](auto& s) -> auto& { return s.blend[i].src_color; }));
      f.push_back(field(
          p + "dst_color", [i](auto& s) -> auto& { return s.blend[i].dst_color; }));
      f.push_back(field(
          p + "color_op", [i](auto& s) -> auto& { return s.blend[i].color_op; }));
      f.push_back(field(
          p + "src_alpha", [i](auto& s) -> auto& { return s.blend[i].src_alpha; }));
      f.push_back(field(
          p + "dst_alpha", [i](auto& s) -> auto& { return s.blend[i].dst_alpha; }));
      f.push_back(field(
          p + "alpha_op", [i](auto& s) -> auto& { return s.blend[i].alpha_op; }));
      f.push_back(field(
          p + "write_mask", [i](auto& s) -> auto& { return s.blend[i].write_mask; }));
    }
    f.push_back(field(
        "rasterizer.polygon_mode", [](auto& s) -> auto& { return s.rasterizer.polygon_mode; }));
    f.push_back(field(
        "rasterizer.cull_mode", [](auto& s) -> auto& { return s.rasterizer.cull_mode; }));
    f.push_back(field(
        "rasterizer.front_face", [](auto& s) -> auto& { return s.rasterizer.front_face; }));
    f.push_back(field(
        "rasterizer.depth_clamp", [](auto& s) -> auto& { return s.rasterizer.depth_clamp; }));
    f.push_back(field(
        "rasterizer.depth_bias", [](auto& s) -> auto& { return s.rasterizer.depth_bias; }));
    f.push_back(field(
        "rasterizer.depth_bias_clamp", [](auto& s) -> auto& { return s.rasterizer.depth_bias_clamp; }));
    f.push_back(field(
        "rasterizer.depth_bias_slope", [](auto& s) -> auto& { return s.rasterizer.depth_bias_slope; }));
    f.push_back(field(
        "depth_stencil.depth_test", [](auto& s) -> auto& { return s.depth_stencil.depth_test; }));
    f.push_back(field(
        "depth_stencil.depth_write", [](auto& s) -> auto& { return s.depth_stencil.depth_write; }));
    f.push_back(field(
        "depth_stencil.depth_compare", [](auto& s) -> auto& { return s.depth_stencil.depth_compare; }));
    f.push_back(field(
        "depth_stencil.stencil_test", [](auto& s) -> auto& { return s.depth_stencil.stencil_test; }));
    add_stencil_fields(f, "front", &DepthStencilState::front);
    add_stencil_fields(f, "back", &DepthStencilState::back);
    return f;
  }();
  return table;
}

std::vector<VkDynamicState> as_set(std::vector<VkDynamicState> states) {
  std::sort(states.begin(), states.end());
  states.erase(std::unique(states.begin(), states.end()), states.end());
  return states;
}

uint64_t constant_bits(const SpecializationConstant& c) {
  uint64_t bits = 0;
  std::memcpy(&bits, c.value.data(), std::min<size_t>(c.size, sizeof bits));
  return bits;
}

// What `settled` changed of `archived`, as a variants file's "state".
Json state_changes(const PatchableState& archived, const PatchableState& settled, bool compute) {
  Json out = Json::object();
  if (!compute) {
    for (const Field& f : fields())
      if (f.differs(archived, settled)) out[f.key] = f.write(settled);
    if (as_set(archived.dynamic_states) != as_set(settled.dynamic_states)) {
      Json& list = out["dynamic_states"] = Json::array();
      for (VkDynamicState d : settled.dynamic_states) list.push_back(vk_name(d));
    }
  }
  Json constants = Json::object();
  for (const SpecializationConstant& c : settled.constants) {
    const SpecializationConstant* before = archived.find_constant(c.name);
    if (!before || constant_bits(*before) != constant_bits(c)) constants[c.name] = constant_bits(c);
  }
  if (!constants.empty()) out["constants"] = std::move(constants);
  return out;
}

std::string pointer_escape(std::string_view key) {
  std::string out;
  for (char c : key) out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return out;
}

// What is wrong with a variant's state: where (a JSON pointer below "state") and why.
struct StateProblem {
  std::string where, reason;
};

// Applies a variant's "state" to `s`. `check_constants`: each constant must be one of s's (false when
// checking a file without its archive).
std::optional<StateProblem> apply_state(const Json& state, bool compute, PatchableState& s,
                                        bool check_constants) {
  if (!state.is_object()) return StateProblem{"", "expected an object of the fields the callback changed"};
  std::vector<std::string> keys;
  for (const Field& f : fields()) keys.push_back(f.key);
  keys.insert(keys.end(), {"dynamic_states", "constants"});
  for (const auto& [key, value] : state.items()) {
    const std::string at = "/" + pointer_escape(key);
    if (key == "constants") {
      if (!value.is_object()) return StateProblem{at, "expected an object of constant names and values"};
      for (const auto& [name, v] : value.items()) {
        const std::string here = at + "/" + pointer_escape(name);
        if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<int64_t>() >= 0))
          return StateProblem{here, "expected the value's bits as an unsigned integer"};
        SpecializationConstant* c = nullptr;
        for (auto& k : s.constants)
          if (k.name == name) c = &k;
        if (!c) {
          if (!check_constants) continue;
          std::vector<std::string> names;
          for (const auto& k : s.constants) names.push_back(k.name);
          return StateProblem{here, "the pipeline has no specialization constant named '" + printable(name) +
                                        "'" + did_you_mean(name, names)};
        }
        const uint64_t bits = v.get<uint64_t>();
        if (c->size < 8 && (bits >> (8 * c->size)) != 0)
          return StateProblem{here, std::to_string(bits) + " does not fit the constant's " +
                                        std::to_string(c->size) + " bytes"};
        c->value = {};
        std::memcpy(c->value.data(), &bits, c->size);
      }
      continue;
    }
    if (compute) return StateProblem{at, "a compute pipeline's variant sets only constants"};
    if (key == "dynamic_states") {
      if (!value.is_array()) return StateProblem{at, "expected an array of VkDynamicState names"};
      std::vector<VkDynamicState> states;
      for (size_t i = 0; i < value.size(); ++i) {
        VkDynamicState d{};
        if (std::string bad = from_json(value[i], d); !bad.empty())
          return StateProblem{at + "/" + std::to_string(i), bad};
        states.push_back(d);
      }
      s.dynamic_states = std::move(states);
      continue;
    }
    auto f = std::find_if(fields().begin(), fields().end(),
                          [&](const Field& candidate) { return candidate.key == key; });
    if (f == fields().end()) return StateProblem{at, "no such field" + did_you_mean(key, keys)};
    if (std::string bad = f->read(value, s); !bad.empty()) return StateProblem{at, bad};
  }
  return std::nullopt;
}

// Nesting deeper than kMaxDepth, found before parsing (outside strings); false when too deep.
bool shallow_enough(std::string_view text) {
  size_t depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxDepth) return false;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return true;
}

Error file_error(std::string_view name, const std::string& where, const std::string& what) {
  return detail::failure(ErrorCode::invalid_argument, "variants file '" + printable(name) + "'" +
                                                          (where.empty() ? "" : " at " + printable(where)) +
                                                          ": " + what);
}

}  // namespace

Result<std::vector<PipelineVariant>> parse_variants(std::string_view text, std::string_view name) {
  return api_guard("parse_variants", [&]() -> Result<std::vector<PipelineVariant>> {
    if (!shallow_enough(text))
      return file_error(name, "",
                        "nested deeper than " + std::to_string(kMaxDepth) + " levels: not a variants file");
    Json doc;
    try {
      doc = Json::parse(text);
    } catch (const Json::exception& e) {  // a syntax error, or a number beyond what a double holds
      std::string what = e.what();
      if (auto at = what.find("] "); at != std::string::npos) what.erase(0, at + 2);
      return file_error(name, "", printable(what));
    }
    if (!doc.is_object()) return file_error(name, "/", "expected an object");
    for (const auto& [key, value] : doc.items())
      if (key != "statepack_variants" && key != "variants")
        return file_error(
            name, "/" + pointer_escape(key),
            "unknown key" + did_you_mean(key, std::vector<std::string>{"statepack_variants", "variants"}));
    auto version = doc.find("statepack_variants");
    if (version == doc.end() || !version->is_number_unsigned() || version->get<uint64_t>() == 0)
      return file_error(name, "/statepack_variants",
                        "missing, or not a version number (this reader writes 1)");
    if (version->get<uint64_t>() > kVariantsVersion)
      return detail::failure(ErrorCode::unsupported_version,
                             "variants file '" + printable(name) + "' has version " +
                                 std::to_string(version->get<uint64_t>()) +
                                 "; this statepack reads version " + std::to_string(kVariantsVersion));
    auto list = doc.find("variants");
    if (list == doc.end() || !list->is_array())
      return file_error(name, "/variants", "missing, or not an array");
    std::vector<PipelineVariant> variants;
    for (size_t i = 0; i < list->size(); ++i) {
      const Json& v = (*list)[i];
      const std::string at = "/variants/" + std::to_string(i);
      if (!v.is_object()) return file_error(name, at, "expected an object");
      for (const auto& [key, value] : v.items())
        if (key != "pipeline" && key != "kind" && key != "state")
          return file_error(
              name, at + "/" + pointer_escape(key),
              "unknown key" + did_you_mean(key, std::vector<std::string>{"pipeline", "kind", "state"}));
      auto pipeline = v.find("pipeline"), kind = v.find("kind"), state = v.find("state");
      if (pipeline == v.end() || !pipeline->is_string())
        return file_error(name, at + "/pipeline", "missing, or not a pipeline name");
      if (kind == v.end() || !kind->is_string() || (*kind != "graphics" && *kind != "compute"))
        return file_error(name, at + "/kind", "expected \"graphics\" or \"compute\"");
      const bool compute = *kind == "compute";
      const Json no_changes = Json::object();
      const Json& changes = state == v.end() ? no_changes : *state;
      PatchableState scratch;
      if (auto bad = apply_state(changes, compute, scratch, false))
        return file_error(name, at + "/state" + bad->where, bad->reason);
      variants.push_back({pipeline->get<std::string>(),
                          compute ? ObjectKind::compute_pipeline : ObjectKind::graphics_pipeline,
                          changes.dump(), "variants file '" + printable(name) + "' at " + at});
    }
    return variants;
  });
}

Result<std::vector<PipelineVariant>> load_variants(const std::filesystem::path& path) {
  return api_guard("load_variants", [&]() -> Result<std::vector<PipelineVariant>> {
    auto file = read_regular_file(path, kMaxVariantsFileBytes);
    if (!file) return file.error();
    const auto bytes = file->bytes();
    return parse_variants(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                          path.string());
  });
}

Result<void> PipelineVariant::apply(PatchableState& s) const {
  return api_guard("PipelineVariant::apply", [&]() -> Result<void> {
    Json changes = Json::parse(state, nullptr, false);
    // A variant read from a file is named by its place there; one made in code by its pipeline.
    const std::string who =
        origin.empty() ? "variant of pipeline '" + printable(pipeline) + "': state" : origin + "/state";
    if (changes.is_discarded() || !shallow_enough(state))
      return detail::failure(ErrorCode::invalid_argument, who + ": not a JSON object of fields");
    if (auto bad = apply_state(changes, kind == ObjectKind::compute_pipeline, s, true))
      return detail::failure(ErrorCode::invalid_argument, who + printable(bad->where) + ": " + bad->reason);
    return {};
  });
}

namespace detail {
std::string recorded_changes(const format::Pipeline& archived, const PatchableState& settled, bool compute) {
  // Constant names are the shaders' (OpName): bytes that are not UTF-8 are replaced, never thrown on.
  return state_changes(to_patchable(archived), settled, compute)
      .dump(-1, ' ', false, Json::error_handler_t::replace);
}
}  // namespace detail

std::vector<PipelineVariant> Dearchiver::variants() const {
  std::lock_guard lock(state_->mutex);
  std::vector<PipelineVariant> out;
  for (const State::Recorded& r : state_->recorded) {
    if (r.gone) continue;
    const bool compute = r.bind_point == VK_PIPELINE_BIND_POINT_COMPUTE;
    const format::Pipeline& p = *r.source.pipeline;
    PipelineVariant v{p.name, compute ? ObjectKind::compute_pipeline : ObjectKind::graphics_pipeline,
                      recorded_changes(p, r.settled, compute)};
    // After a reload two entries may have come to say the same (each distinct variant is listed once).
    if (std::none_of(out.begin(), out.end(), [&](const PipelineVariant& o) {
          return o.pipeline == v.pipeline && o.kind == v.kind && o.state == v.state;
        }))
      out.push_back(std::move(v));
  }
  return out;
}

Result<void> Dearchiver::save_variants(const std::filesystem::path& path) const {
  return api_guard("Dearchiver::save_variants", [&]() -> Result<void> {
    Json doc = Json::object();
    doc["statepack_variants"] = kVariantsVersion;
    Json& list = doc["variants"] = Json::array();
    for (const PipelineVariant& v : variants())
      list.push_back({{"pipeline", v.pipeline},
                      {"kind", v.kind == ObjectKind::compute_pipeline ? "compute" : "graphics"},
                      {"state", Json::parse(v.state)}});
    // Names are written as the archive has them; invalid UTF-8 is replaced, not refused.
    const std::string text = doc.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
    return save_file_atomically(path, {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
  });
}

Result<const UnpackedPipeline*> Dearchiver::unpack_variant(const PipelineVariant& variant) {
  return api_guard("Dearchiver::unpack_variant", [&]() -> Result<const UnpackedPipeline*> {
    std::optional<Error> bad;  // the variant's own error, rather than "the modify callback threw"
    struct Refused {};
    const ModifyCallback apply = [&](PatchableState& s) {
      if (auto ok = variant.apply(s); !ok) {
        bad = ok.error();
        throw Refused{};
      }
    };
    auto made = variant.kind == ObjectKind::compute_pipeline ? unpack_compute(variant.pipeline, apply)
                                                             : unpack_graphics(variant.pipeline, apply);
    if (bad) return *bad;
    if (made || variant.origin.empty()) return made;
    if (made.error().code == ErrorCode::wrong_type)  // the file's "kind" names the other kind
      return detail::failure(ErrorCode::wrong_type, variant.origin + "/kind: " + made.error().message);
    if (made.error().code != ErrorCode::invalid_argument) return made;
    // The checks after the callback are the ones every callback's values get, and say so; here the
    // values are the file's, so the message names the variant's place in it instead.
    std::string message = made.error().message;
    for (size_t at = 0; (at = message.find("the modify callback", at)) != std::string::npos;)
      message.replace(at, 19, "the variant");
    return detail::failure(ErrorCode::invalid_argument, variant.origin + ": " + message);
  });
}

}  // namespace statepack
