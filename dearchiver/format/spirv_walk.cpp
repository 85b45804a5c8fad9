// SPIR-V walk: one pass records the instructions we need, a second resolves variables to what the
// layout must provide. Every read is bounded by the instruction's own word count, every id by the
// header's bound, and type recursion by a depth limit, so hostile words yield errors, not crashes.
#include "spirv_walk.hpp"

#include "support/failure.hpp"

#include "spirv_structure.hpp"

#include <vulkan/vulkan_core.h>

#include <algorithm>
#include <map>
#include <unordered_map>
#include <unordered_set>

namespace statepack::spirv {
namespace {

constexpr uint32_t kMagic = 0x07230203u;
constexpr uint32_t kMaxBound = 4194303;  // SPIR-V's universal limit on the id bound
constexpr int kMaxTypeDepth = 16;        // nesting deeper than this is treated as hostile
constexpr size_t kMaxEntryPoints = 1024;
constexpr uint64_t kMaxSizeSteps = 1 << 16;  // type visits spent sizing push constant blocks

enum Op : uint32_t {
  kOpName = 5,
  kOpEntryPoint = 15,
  kOpExecutionMode = 16,
  kOpCapability = 17,
  kOpTypeBool = 20,
  kOpTypeInt = 21,
  kOpTypeFloat = 22,
  kOpTypeVector = 23,
  kOpTypeMatrix = 24,
  kOpTypeImage = 25,
  kOpTypeSampler = 26,
  kOpTypeSampledImage = 27,
  kOpTypeArray = 28,
  kOpTypeRuntimeArray = 29,
  kOpTypeStruct = 30,
  kOpTypePointer = 32,
  kOpConstant = 43,
  kOpConstantComposite = 44,
  kOpSpecConstantTrue = 48,
  kOpSpecConstantFalse = 49,
  kOpSpecConstant = 50,
  kOpSpecConstantComposite = 51,
  kOpVariable = 59,
  kOpDecorate = 71,
  kOpMemberDecorate = 72,
  kOpFunction = 54,
  kOpFunctionParameter = 55,
  kOpFunctionEnd = 56,
  kOpAccessChain = 65,
  kOpInBoundsAccessChain = 66,
  kOpStore = 62,
  kOpLabel = 248,
  kOpExecutionModeId = 331,
};
constexpr uint32_t kExecutionModeLocalSize = 17, kExecutionModeLocalSizeId = 38;
constexpr uint32_t kExecutionModelGLCompute = 5;

// Instructions that end a block.
bool is_terminator(uint32_t op) {
  return (op >= 249 && op <= 255) || op == 4416 /* OpTerminateInvocation */ ||
         op == 4448 /* OpIgnoreIntersectionKHR */ || op == 4449 /* OpTerminateRayKHR */ ||
         op == 5294 /* OpEmitMeshTasksEXT */;
}
enum Decoration : uint32_t {
  kSpecId = 1,
  kBlock = 2,
  kBufferBlock = 3,
  kRowMajor = 4,
  kArrayStride = 6,
  kMatrixStride = 7,
  kBuiltIn = 11,
  kLocation = 30,
  kBinding = 33,
  kDescriptorSet = 34,
  kOffset = 35,
};
constexpr uint32_t kBuiltInPointSize = 1, kBuiltInWorkgroupSize = 25;
enum StorageClass : uint32_t {
  kUniformConstant = 0,
  kInput = 1,
  kUniform = 2,
  kOutput = 3,
  kPushConstant = 9,
  kStorageBuffer = 12,
};
enum Dim : uint32_t { kDimBuffer = 5, kDimSubpassData = 6 };

constexpr DescriptorTypeMask bit(uint32_t descriptor_type) {
  return 1u << descriptor_type;
}
// VkDescriptorType values.
constexpr uint32_t kSampler = 0, kCombined = 1, kSampledImage = 2, kStorageImage = 3, kUniformTexel = 4,
                   kStorageTexel = 5, kUniformBuffer = 6, kStorageBuffer_ = 7, kUniformDynamic = 8,
                   kStorageDynamic = 9, kInputAttachment = 10;

struct Decorations {
  std::optional<uint32_t> set, binding, location, array_stride, spec_id;
  bool block = false, buffer_block = false, builtin = false, point_size = false;
};
struct MemberDecorations {
  std::optional<uint32_t> offset, matrix_stride;
  bool row_major = false, point_size = false;
};

// Values by result id. Ids are below the module's bound, which a real module keeps to a fifth of its
// words or less, so a table indexed by id (4 bytes an id, made on the first value) finds a value
// without hashing, and the values sit side by side without an allocation each; a bound beyond the
// words (a hostile header: up to 4 million) falls back to a hash map, so that memory stays in proportion
// to the words. A reference from operator[] lasts until the next value is added.
template <class T>
class IdTable {
 public:
  void size_for(uint32_t bound, size_t words) {
    bound_ = bound;
    dense_ = bound <= words + 64;
  }
  T& operator[](uint32_t id) {  // id below the bound (the caller checked)
    if (!dense_) return sparse_[id];
    if (slot_.empty()) slot_.assign(bound_, 0);
    uint32_t& slot = slot_[id];
    if (slot == 0) {
      values_.emplace_back();
      slot = static_cast<uint32_t>(values_.size());
    }
    return values_[slot - 1];
  }
  const T* find(uint32_t id) const {
    if (!dense_) {
      auto it = sparse_.find(id);
      return it == sparse_.end() ? nullptr : &it->second;
    }
    return id < slot_.size() && slot_[id] != 0 ? &values_[slot_[id] - 1] : nullptr;
  }

 private:
  uint32_t bound_ = 0;
  bool dense_ = false;
  std::vector<uint32_t> slot_;  // by id: 1 + the value's index, or 0 for none
  std::vector<T> values_;
  std::unordered_map<uint32_t, T> sparse_;
};

struct TypeInfo {
  uint32_t op = 0;
  std::span<const uint32_t> operands;  // after the result id
};

struct Walker {
  std::span<const uint32_t> words;
  Module module;
  IdTable<TypeInfo> types;
  IdTable<uint32_t> constants;  // 32-bit integer constants
  IdTable<Decorations> decorations;
  std::map<std::pair<uint32_t, uint32_t>, MemberDecorations> members;
  struct Variable {
    uint32_t id, pointer_type, storage;
  };
  std::vector<Variable> variables;
  std::vector<std::pair<uint32_t, uint32_t>> spec_constants;  // (result id, result type)
  IdTable<uint32_t> spec_defaults;                            // OpSpecConstant id -> its (low) word
  IdTable<std::span<const uint32_t>> composites;              // (spec) constant composites
  // Work-group sizes: LocalSize literals and LocalSizeId ids by entry function, the WorkgroupSize id.
  std::unordered_map<uint32_t, std::array<uint32_t, 3>> local_size, local_size_id;
  std::optional<uint32_t> workgroup_size_builtin;
  // Hash containers keep every lookup below constant-time: a hostile module of a million words
  // must not turn the walk quadratic.
  std::unordered_set<uint32_t> stores;                                             // pointers stored to
  std::unordered_multimap<uint32_t, std::pair<uint32_t, uint32_t>> access_chains;  // base -> id, first index
  mutable uint64_t size_steps = 0;  // work spent in size_of, which branches over struct members

  [[gnu::cold]] static Error fail(size_t at, const std::string& what) {
    return detail::failure(ErrorCode::corrupt, "SPIR-V word " + std::to_string(at) + ": " + what);
  }

  Result<void> record(size_t at, uint32_t op, std::span<const uint32_t> operands) {
    auto need = [&](size_t n) { return operands.size() >= n; };
    auto id_ok = [&](uint32_t id) { return id != 0 && id < module.bound; };
    switch (op) {
      case kOpCapability:
        if (!need(1)) return fail(at, "OpCapability is too short");
        module.capabilities.push_back(operands[0]);
        return {};
      case kOpEntryPoint: {
        if (!need(3)) return fail(at, "OpEntryPoint is too short");
        EntryPoint entry;
        entry.execution_model = operands[0];
        entry.function = operands[1];
        // The name is a NUL-terminated literal packed four bytes a word, inside the instruction.
        const auto* bytes = reinterpret_cast<const char*>(operands.data() + 2);
        const size_t max_bytes = (operands.size() - 2) * 4;
        const auto length = static_cast<size_t>(std::find(bytes, bytes + max_bytes, '\0') - bytes);
        if (length == max_bytes) return fail(at, "OpEntryPoint name is not NUL-terminated");
        entry.name.assign(bytes, length);
        for (size_t i = 2 + length / 4 + 1; i < operands.size(); ++i) entry.interface.push_back(operands[i]);
        module.entry_points.push_back(std::move(entry));
        return {};
      }
      case kOpExecutionMode:
      case kOpExecutionModeId:
        if (need(5) && (operands[1] == kExecutionModeLocalSize || operands[1] == kExecutionModeLocalSizeId))
          (operands[1] == kExecutionModeLocalSize ? local_size : local_size_id)[operands[0]] = {
              operands[2], operands[3], operands[4]};
        return {};
      case kOpConstantComposite:
      case kOpSpecConstantComposite:
        if (need(2) && id_ok(operands[1])) composites[operands[1]] = operands.subspan(2);
        return {};
      case kOpTypeBool:
      case kOpTypeInt:
      case kOpTypeFloat:
      case kOpTypeVector:
      case kOpTypeMatrix:
      case kOpTypeImage:
      case kOpTypeSampler:
      case kOpTypeSampledImage:
      case kOpTypeArray:
      case kOpTypeRuntimeArray:
      case kOpTypeStruct:
      case kOpTypePointer: {
        if (!need(1) || !id_ok(operands[0])) return fail(at, "type instruction without a valid result id");
        static constexpr std::pair<uint32_t, size_t> kOperands[] = {
            {kOpTypeInt, 3},    {kOpTypeFloat, 2},        {kOpTypeVector, 3},
            {kOpTypeMatrix, 3}, {kOpTypeImage, 8},        {kOpTypeSampledImage, 2},
            {kOpTypeArray, 3},  {kOpTypeRuntimeArray, 2}, {kOpTypePointer, 3}};
        for (auto [type_op, n] : kOperands)
          if (type_op == op && !need(n)) return fail(at, "type instruction is too short");
        types[operands[0]] = {op, operands.subspan(1)};
        return {};
      }
      case kOpStore:
        if (need(1)) stores.insert(operands[0]);
        return {};
      case kOpAccessChain:
      case kOpInBoundsAccessChain:
        if (need(4)) access_chains.emplace(operands[2], std::pair{operands[1], operands[3]});
        return {};
      case kOpConstant:
        if (need(3) && id_ok(operands[1])) constants[operands[1]] = operands[2];
        return {};
      case kOpSpecConstantTrue:
      case kOpSpecConstantFalse:
      case kOpSpecConstant:
        if (!need(2) || !id_ok(operands[1])) return fail(at, "OpSpecConstant is too short or has a bad id");
        spec_constants.emplace_back(operands[1], operands[0]);  // (id, type)
        if (op == kOpSpecConstant && need(3)) spec_defaults[operands[1]] = operands[2];
        return {};
      case kOpVariable:
        if (!need(3) || !id_ok(operands[1])) return fail(at, "OpVariable is too short or has a bad id");
        variables.push_back({operands[1], operands[0], operands[2]});
        return {};
      case kOpDecorate: {
        if (!need(2) || !id_ok(operands[0])) return fail(at, "OpDecorate is too short or has a bad target");
        Decorations& d = decorations[operands[0]];
        const uint32_t kind = operands[1];
        const bool has_value = need(3);
        if (kind == kBlock) d.block = true;
        if (kind == kBufferBlock) d.buffer_block = true;
        if (kind == kBuiltIn) d.builtin = true, d.point_size = has_value && operands[2] == kBuiltInPointSize;
        if (kind == kBuiltIn && has_value && operands[2] == kBuiltInWorkgroupSize)
          workgroup_size_builtin = operands[0];
        if (kind == kDescriptorSet || kind == kBinding || kind == kLocation || kind == kArrayStride ||
            kind == kSpecId) {
          if (!has_value) return fail(at, "OpDecorate lacks its value");
          if (kind == kSpecId) d.spec_id = operands[2];
          if (kind == kDescriptorSet) d.set = operands[2];
          if (kind == kBinding) d.binding = operands[2];
          if (kind == kLocation) d.location = operands[2];
          if (kind == kArrayStride) d.array_stride = operands[2];
        }
        return {};
      }
      case kOpMemberDecorate: {
        if (!need(3) || !id_ok(operands[0]))
          return fail(at, "OpMemberDecorate is too short or has a bad target");
        MemberDecorations& m = members[{operands[0], operands[1]}];
        const uint32_t kind = operands[2];
        if (kind == kRowMajor) m.row_major = true;
        if (kind == kBuiltIn && need(4) && operands[3] == kBuiltInPointSize) m.point_size = true;
        if (kind == kOffset || kind == kMatrixStride) {
          if (!need(4)) return fail(at, "OpMemberDecorate lacks its value");
          (kind == kOffset ? m.offset : m.matrix_stride) = operands[3];
        }
        return {};
      }
      default:
        return {};
    }
  }
  // The opcode and operands (after the result id) of a type, or none.
  std::optional<std::pair<uint32_t, std::span<const uint32_t>>> type(uint32_t id) const {
    const TypeInfo* t = types.find(id);
    if (!t) return std::nullopt;
    return std::pair{t->op, t->operands};
  }

  // Descriptor types a UniformConstant / Uniform / StorageBuffer variable's (array-stripped) type fits.
  DescriptorTypeMask classify(uint32_t type_id, uint32_t storage) const {
    auto t = type(type_id);
    if (!t) return 0;
    auto [op, o] = *t;
    if (storage == kStorageBuffer) return bit(kStorageBuffer_) | bit(kStorageDynamic);
    if (storage == kUniform) {
      const Decorations* d = decorations.find(type_id);
      if (op != kOpTypeStruct || !d) return 0;
      if (d->block) return bit(kUniformBuffer) | bit(kUniformDynamic);
      if (d->buffer_block) return bit(kStorageBuffer_) | bit(kStorageDynamic);
      return 0;
    }
    if (op == kOpTypeSampler) return bit(kSampler) | bit(kCombined);
    if (op == kOpTypeSampledImage) {
      auto image = type(o[0]);
      if (image && image->first == kOpTypeImage && image->second[1] == kDimBuffer) return bit(kUniformTexel);
      return bit(kCombined);
    }
    if (op == kOpTypeImage) {
      const uint32_t dim = o[1], sampled = o[5];
      if (dim == kDimSubpassData) return bit(kInputAttachment);
      if (dim == kDimBuffer)
        return sampled == 1   ? bit(kUniformTexel)
               : sampled == 2 ? bit(kStorageTexel)
                              : bit(kUniformTexel) | bit(kStorageTexel);
      if (sampled == 1) return bit(kSampledImage) | bit(kCombined);
      if (sampled == 2) return bit(kStorageImage);
      return bit(kSampledImage) | bit(kCombined) | bit(kStorageImage);
    }
    return 0;
  }

  // Bytes a type spans in a block, or 0 when not computed here (then only "non-zero" is checked).
  uint64_t size_of(uint32_t type_id, const MemberDecorations* member, int depth) const {
    auto t = type(type_id);
    // Structs of structs branch: nesting alone could make this exponential, so the work is bounded.
    if (!t || depth > kMaxTypeDepth || ++size_steps > kMaxSizeSteps) return 0;
    auto [op, o] = *t;
    switch (op) {
      case kOpTypeInt:
      case kOpTypeFloat:
        return o[0] / 8;
      case kOpTypeVector:
        return uint64_t(o[1]) * size_of(o[0], nullptr, depth + 1);
      case kOpTypeMatrix: {
        if (!member || !member->matrix_stride) return 0;
        auto column = type(o[0]);
        if (!column || column->first != kOpTypeVector) return 0;
        const uint64_t vectors = member->row_major ? column->second[1] : o[1];
        return vectors * *member->matrix_stride;
      }
      case kOpTypeArray: {
        const uint32_t* length = constants.find(o[1]);
        const Decorations* d = decorations.find(type_id);
        if (!length || !d || !d->array_stride) return 0;
        return uint64_t(*length) * *d->array_stride;
      }
      case kOpTypeStruct: {
        uint64_t end = 0;
        for (uint32_t m = 0; m < o.size(); ++m) {
          auto it = members.find({type_id, m});
          if (it == members.end() || !it->second.offset) return 0;
          const uint64_t size = size_of(o[m], &it->second, depth + 1);
          if (size == 0) return 0;
          end = std::max(end, *it->second.offset + size);
        }
        return end;
      }
      default:
        return 0;
    }
  }

  // Locations an Input variable's type occupies.
  uint32_t locations_of(uint32_t type_id, int depth) const {
    auto t = type(type_id);
    if (!t || depth > kMaxTypeDepth) return 1;
    auto [op, o] = *t;
    if (op == kOpTypeArray) {
      const uint32_t* length = constants.find(o[1]);
      const uint64_t n = length ? *length : 1;
      return static_cast<uint32_t>(std::min<uint64_t>(n * locations_of(o[0], depth + 1), 0xFFFFu));
    }
    if (op == kOpTypeMatrix) return o[1];
    return 1;
  }

  // Component type of a scalar, vector or array of them.
  Numeric numeric_of(uint32_t type_id, int depth) const {
    auto t = type(type_id);
    if (!t || depth > kMaxTypeDepth) return Numeric::other;
    auto [op, o] = *t;
    if (op == kOpTypeFloat) return Numeric::float_;
    if (op == kOpTypeInt) return o[1] ? Numeric::sint : Numeric::uint;
    if (op == kOpTypeVector || op == kOpTypeArray || op == kOpTypeMatrix) return numeric_of(o[0], depth + 1);
    return Numeric::other;
  }

  // Whether a store reaches the PointSize built-in through this Output variable: directly, or through
  // an access chain into the member of gl_PerVertex that carries it (how compilers write it).
  bool writes_point_size(uint32_t variable, uint32_t pointee, const Decorations* d) const {
    if (d && d->point_size) return stores.count(variable) > 0;
    auto [first, last] = access_chains.equal_range(variable);
    for (auto it = first; it != last; ++it) {
      const auto [id, index_id] = it->second;
      const uint32_t* index = constants.find(index_id);
      if (!index) continue;
      auto member = members.find({pointee, *index});
      if (member != members.end() && member->second.point_size && stores.count(id)) return true;
    }
    return false;
  }

  // A work-group dimension from a constant's id: an OpConstant, or a specialization constant's default
  // with its SpecId (one without a SpecId cannot be overridden: its default is the value).
  std::optional<WorkgroupDim> dimension(uint32_t id) const {
    if (const uint32_t* c = constants.find(id)) return WorkgroupDim{*c, std::nullopt};
    const uint32_t* s = spec_defaults.find(id);
    if (!s) return std::nullopt;
    const Decorations* d = decorations.find(id);
    return WorkgroupDim{*s, d ? d->spec_id : std::nullopt};
  }
  std::optional<std::array<WorkgroupDim, 3>> dimensions(std::span<const uint32_t> ids) const {
    if (ids.size() != 3) return std::nullopt;
    std::array<WorkgroupDim, 3> out;
    for (size_t i = 0; i < 3; ++i) {
      auto dim = dimension(ids[i]);
      if (!dim) return std::nullopt;
      out[i] = *dim;
    }
    return out;
  }
  std::optional<std::array<WorkgroupDim, 3>> workgroup_size_of(uint32_t function) const {
    if (workgroup_size_builtin) {
      const std::span<const uint32_t>* composite = composites.find(*workgroup_size_builtin);
      return composite ? dimensions(*composite) : std::nullopt;
    }
    if (auto ids = local_size_id.find(function); ids != local_size_id.end()) return dimensions(ids->second);
    if (auto sizes = local_size.find(function); sizes != local_size.end())
      return std::array<WorkgroupDim, 3>{WorkgroupDim{sizes->second[0], {}},
                                         WorkgroupDim{sizes->second[1], {}},
                                         WorkgroupDim{sizes->second[2], {}}};
    return std::nullopt;
  }

  Result<void> resolve() {
    for (EntryPoint& entry : module.entry_points)
      if (entry.execution_model == kExecutionModelGLCompute)
        entry.workgroup_size = workgroup_size_of(entry.function);
    for (auto [id, type_id] : spec_constants) {
      const Decorations* d = decorations.find(id);
      if (!d || !d->spec_id) continue;  // not specializable
      auto t = type(type_id);
      uint32_t size = 0;
      SpecKind kind = SpecKind::other;
      if (t && t->first == kOpTypeBool) size = 4, kind = SpecKind::boolean;  // VkBool32
      if (t && (t->first == kOpTypeInt || t->first == kOpTypeFloat) &&
          (t->second[0] == 32 || t->second[0] == 64)) {
        size = t->second[0] / 8;
        kind = t->first == kOpTypeFloat                    ? SpecKind::float_
               : t->second.size() > 1 && t->second[1] != 0 ? SpecKind::sint
                                                           : SpecKind::uint;
      }
      module.spec_constants.push_back({*d->spec_id, size, kind});
    }
    std::sort(module.spec_constants.begin(), module.spec_constants.end(),
              [](const SpecConstant& a, const SpecConstant& b) { return a.constant_id < b.constant_id; });
    for (const Variable& v : variables) {
      auto pointer = type(v.pointer_type);
      if (!pointer || pointer->first != kOpTypePointer) continue;  // checked by the driver, not needed here
      uint32_t pointee = pointer->second[1];
      const Decorations* d = decorations.find(v.id);
      if (v.storage == kUniformConstant || v.storage == kUniform || v.storage == kStorageBuffer) {
        Resource r;
        r.variable = v.id;
        uint64_t elements = 1;
        for (int depth = 0; depth < kMaxTypeDepth; ++depth) {  // arrays of resources
          auto t = type(pointee);
          if (!t || (t->first != kOpTypeArray && t->first != kOpTypeRuntimeArray)) break;
          if (t->first == kOpTypeRuntimeArray) {
            elements = 0;
          } else if (const uint32_t* length = constants.find(t->second[1])) {
            elements = std::min<uint64_t>(elements * *length, 0xFFFFFFFFu);
          }
          pointee = t->second[0];
        }
        r.array_size = static_cast<uint32_t>(elements);
        r.compatible = classify(pointee, v.storage);
        if (!d || !d->set || !d->binding)
          return detail::failure(ErrorCode::corrupt,
                                 "variable %" + std::to_string(v.id) + " has no descriptor set or binding");
        r.set = *d->set;
        r.binding = *d->binding;
        module.resources.push_back(r);
      } else if (v.storage == kPushConstant) {
        if (module.push_constants)
          return detail::failure(ErrorCode::corrupt, "more than one push constant block");
        module.push_constants = PushConstantBlock{
            v.id, static_cast<uint32_t>(std::min<uint64_t>(size_of(pointee, nullptr, 0), 0xFFFFFFFFu))};
      } else if (v.storage == kOutput && writes_point_size(v.id, pointee, d)) {
        module.writes_point_size = true;
      } else if ((v.storage == kInput || v.storage == kOutput) && d && d->location && !d->builtin) {
        (v.storage == kInput ? module.inputs : module.outputs)
            .push_back({v.id, *d->location, locations_of(pointee, 0), numeric_of(pointee, 0)});
      }
    }
    return {};
  }
};

}  // namespace

const EntryPoint* Module::find(uint32_t execution_model, std::string_view name) const {
  for (const auto& e : entry_points)
    if (e.execution_model == execution_model && e.name == name) return &e;
  return nullptr;
}

const SpecConstant* Module::find_spec_constant(uint32_t constant_id) const {
  auto it = std::lower_bound(spec_constants.begin(), spec_constants.end(), constant_id,
                             [](const SpecConstant& s, uint32_t id) { return s.constant_id < id; });
  return it != spec_constants.end() && it->constant_id == constant_id ? &*it : nullptr;
}

uint32_t Module::output_location_mask() const {
  uint32_t mask = 0;
  for (const Input& o : outputs)
    for (uint64_t l = o.location; l < uint64_t(o.location) + o.locations && l < 32; ++l) mask |= 1u << l;
  return mask;
}

bool Module::uses(const EntryPoint& entry, uint32_t variable) const {
  if (version < 0x00010400u) return true;
  return std::binary_search(entry.interface.begin(), entry.interface.end(), variable);  // sorted by walk()
}

Result<Module> walk(std::span<const uint32_t> words) {
  if (words.size() < 5)
    return detail::failure(ErrorCode::corrupt, "SPIR-V module is shorter than its 5-word header");
  if (words[0] != kMagic)
    return detail::failure(ErrorCode::corrupt, "SPIR-V module has the wrong magic number");
  const uint32_t version = words[1];
  if ((version & 0xFF0000FFu) != 0 || version < 0x00010000u || version > 0x00010600u)
    return detail::failure(ErrorCode::corrupt,
                           "SPIR-V module has an unknown version word " + std::to_string(version));
  if (words[3] == 0 || words[3] > kMaxBound)
    return detail::failure(ErrorCode::corrupt,
                           "SPIR-V module has an invalid id bound " + std::to_string(words[3]));
  if (words[4] != 0) return detail::failure(ErrorCode::corrupt, "SPIR-V module has a non-zero schema word");
  if (auto ok = check_structure(words); !ok) return ok.error();
  Walker w;
  w.words = words;
  w.module.version = version;
  w.module.bound = words[3];
  w.types.size_for(w.module.bound, words.size());
  w.constants.size_for(w.module.bound, words.size());
  w.decorations.size_for(w.module.bound, words.size());
  w.spec_defaults.size_for(w.module.bound, words.size());
  w.composites.size_for(w.module.bound, words.size());
  // Function structure is checked too: a module cut at an instruction boundary (a shortened blob) must
  // not reach the validation layer or the driver, which assume every function and block is closed.
  bool in_function = false, in_block = false;
  std::unordered_set<uint32_t> functions;
  for (size_t at = 5; at < words.size();) {
    const uint32_t count = words[at] >> 16, op = words[at] & 0xFFFFu;
    if (count == 0) return Walker::fail(at, "instruction with a word count of zero");
    if (count > words.size() - at) return Walker::fail(at, "instruction runs past the end of the module");
    if (auto ok = w.record(at, op, words.subspan(at + 1, count - 1)); !ok) return ok.error();
    if (op == kOpFunction) {
      if (in_function || count < 5) return Walker::fail(at, "OpFunction inside a function or too short");
      in_function = true;
      functions.insert(words[at + 2]);
    } else if (op == kOpFunctionEnd) {
      if (!in_function || in_block)
        return Walker::fail(at, "OpFunctionEnd outside a function or inside a block");
      in_function = false;
    } else if (op == kOpLabel) {
      if (!in_function || in_block) return Walker::fail(at, "OpLabel outside a function or inside a block");
      in_block = true;
    } else if (is_terminator(op)) {
      if (!in_block) return Walker::fail(at, "block terminator outside a block");
      in_block = false;
    } else if (in_function && !in_block && op != kOpFunctionParameter && op != 8 /* OpLine */ &&
               op != 317 /* OpNoLine */) {
      return Walker::fail(at, "instruction outside a block of its function");
    }
    at += count;
  }
  if (in_function) return detail::failure(ErrorCode::corrupt, "SPIR-V module ends inside a function");
  for (auto& entry : w.module.entry_points) std::sort(entry.interface.begin(), entry.interface.end());
  if (w.module.entry_points.empty())
    return detail::failure(ErrorCode::corrupt, "SPIR-V module has no entry point");
  // Entry points are looked up linearly per shader record; real modules have a handful.
  if (w.module.entry_points.size() > kMaxEntryPoints)
    return detail::failure(ErrorCode::corrupt, "SPIR-V module declares more than " +
                                                   std::to_string(kMaxEntryPoints) + " entry points");
  for (const auto& entry : w.module.entry_points)
    if (!functions.count(entry.function))
      return detail::failure(ErrorCode::corrupt,
                             "SPIR-V entry point '" + entry.name + "' names no function of the module");
  if (auto ok = w.resolve(); !ok) return detail::failure(ErrorCode::corrupt, "SPIR-V " + ok.error().message);
  return std::move(w.module);
}

WorkgroupSize specialized_workgroup_size(
    const std::array<WorkgroupDim, 3>& dims,
    const std::function<std::optional<uint32_t>(uint32_t)>& specialized) {
  WorkgroupSize size{};
  for (size_t i = 0; i < 3; ++i) {
    const auto value = dims[i].spec_id ? specialized(*dims[i].spec_id) : std::nullopt;
    size[i] = value ? *value : dims[i].value;
  }
  return size;
}

std::string workgroup_size_text(const WorkgroupSize& size) {
  return std::to_string(size[0]) + " x " + std::to_string(size[1]) + " x " + std::to_string(size[2]);
}

std::optional<uint32_t> execution_model_of_stage(uint32_t stage) {
  switch (stage) {
    case 0x01:
      return 0;  // Vertex
    case 0x02:
      return 1;  // TessellationControl
    case 0x04:
      return 2;  // TessellationEvaluation
    case 0x08:
      return 3;  // Geometry
    case 0x10:
      return 4;  // Fragment
    case 0x20:
      return 5;  // GLCompute
    default:
      return std::nullopt;
  }
}

const char* stage_name(uint32_t stage) {
  switch (stage) {
    case 0x01:
      return "vertex";
    case 0x02:
      return "tessellation control";
    case 0x04:
      return "tessellation evaluation";
    case 0x08:
      return "geometry";
    case 0x10:
      return "fragment";
    case 0x20:
      return "compute";
    default:
      return "unknown";
  }
}

Numeric numeric_of_format(uint32_t f) {
  auto in_group = [&](uint32_t first, uint32_t last, uint32_t size,
                      uint32_t uint_at) -> std::optional<Numeric> {
    if (f < first || f > last) return std::nullopt;
    const uint32_t at = (f - first) % size;
    return at == uint_at ? Numeric::uint : at == uint_at + 1 ? Numeric::sint : Numeric::float_;
  };
  if (auto n = in_group(VK_FORMAT_R8_UNORM, VK_FORMAT_A8B8G8R8_SRGB_PACK32, 7, 4)) return *n;
  if (auto n = in_group(VK_FORMAT_A2R10G10B10_UNORM_PACK32, VK_FORMAT_A2B10G10R10_SINT_PACK32, 6, 4))
    return *n;
  if (auto n = in_group(VK_FORMAT_R16_UNORM, VK_FORMAT_R16G16B16A16_SFLOAT, 7, 4)) return *n;
  if (auto n = in_group(VK_FORMAT_R32_UINT, VK_FORMAT_R64G64B64A64_SFLOAT, 3, 0)) return *n;
  if (f == VK_FORMAT_S8_UINT) return Numeric::uint;
  return f == VK_FORMAT_UNDEFINED ? Numeric::other : Numeric::float_;
}

}  // namespace statepack::spirv
