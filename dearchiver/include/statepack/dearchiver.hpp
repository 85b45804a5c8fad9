// libstatepack_dearchiver — unpacks statepack archives into Vulkan objects.
//
//   auto archive = statepack::Archive::from_file("scene.spk");          // or from_memory(bytes)
//   if (!archive) return fail(archive.error());                         // every call returns a Result
//   auto dearchiver = statepack::Dearchiver::create({physical_device, device});
//   if (!dearchiver || !dearchiver->add_archive(std::move(*archive))) return ...;
//   auto pso = dearchiver->unpack_graphics("Resolve PSO", [&](statepack::PatchableState& s) {
//     s.color_formats[0] = swapchain_format;                            // run-time-only state
//   });
//   if (!pso) return fail(pso.error());                                 // names the pipeline and why
//   vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, (*pso)->pipeline);
//
// docs/api.md has the complete program (compiled by the test suite) and every PatchableState field.
//
// The dearchiver owns every Vulkan object it creates and destroys them with itself. Shader modules
// and descriptor set layouts are created once and shared between pipelines. No shader compiler is
// linked: the archive holds final SPIR-V whose bindings already match the stored layouts.
#pragma once

#include <vulkan/vulkan.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "statepack/export.hpp"
#include "statepack/result.hpp"

namespace statepack {

namespace detail {
struct ArchiveAccess;  // the dearchiver's own view of the decoded archive
}

enum class ObjectKind { graphics_pipeline, compute_pipeline, resource_signature, render_pass, shader };

// A named object of an archive, as unpack_* calls name it.
struct ObjectInfo {
  std::string name;
  ObjectKind kind;
};

// A loaded, fully validated archive. Owns its bytes (from_file) or borrows them (from_memory).
class STATEPACK_API Archive {
 public:
  // Reads and validates a file. `required_content_version`, when set, must equal the archive's.
  static Result<Archive> from_file(const std::filesystem::path& path,
                                   std::optional<uint32_t> required_content_version = std::nullopt);
  // Validates caller-owned memory without copying it; `bytes` must stay alive and unchanged while the
  // Archive (or a Dearchiver it was added to) exists, and must be 4-byte aligned.
  static Result<Archive> from_memory(std::span<const uint8_t> bytes,
                                     std::optional<uint32_t> required_content_version = std::nullopt);

  Archive(Archive&&) noexcept;
  Archive& operator=(Archive&&) noexcept;
  ~Archive();

  uint32_t content_version() const;
  uint32_t format_version() const;
  // Every named object: pipelines, resource signatures, render passes, standalone shaders.
  std::vector<ObjectInfo> objects() const;

 private:
  friend struct detail::ArchiveAccess;
  struct State;
  explicit Archive(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

struct BlendAttachmentState {
  bool enable = false;
  VkBlendFactor src_color = VK_BLEND_FACTOR_ONE, dst_color = VK_BLEND_FACTOR_ZERO;
  VkBlendOp color_op = VK_BLEND_OP_ADD;
  VkBlendFactor src_alpha = VK_BLEND_FACTOR_ONE, dst_alpha = VK_BLEND_FACTOR_ZERO;
  VkBlendOp alpha_op = VK_BLEND_OP_ADD;
  VkColorComponentFlags write_mask = 0xF;
};

struct RasterizerState {
  VkPolygonMode polygon_mode = VK_POLYGON_MODE_FILL;
  VkCullModeFlags cull_mode = VK_CULL_MODE_BACK_BIT;
  VkFrontFace front_face = VK_FRONT_FACE_CLOCKWISE;
  bool depth_clamp = false;
  float depth_bias = 0, depth_bias_clamp = 0, depth_bias_slope = 0;
};

struct DepthStencilState {
  bool depth_test = true, depth_write = true;
  VkCompareOp depth_compare = VK_COMPARE_OP_LESS;
  bool stencil_test = false;
  VkStencilOpState front{}, back{};
};

// A specialization constant of a pipeline, by the name its shaders give it (an OpName, e.g. GLSL's
// `layout(constant_id = 0) const uint kCount = 64;` is "kCount").
struct SpecializationConstant {
  std::string name;
  VkShaderStageFlags stages = 0;   // the stages whose shaders declare it
  uint32_t size = 4;               // bytes: 4 (bool as VkBool32, int, uint, float) or 8 (double, 64-bit int)
  std::array<uint8_t, 8> value{};  // little-endian; `size` bytes are used

  // The value as T (sizeof(T) must be `size`; bool reads a VkBool32).
  template <class T>
  T get() const {
    if constexpr (std::is_same_v<T, bool>) return get<uint32_t>() != 0;
    T out{};
    std::memcpy(&out, value.data(), std::min<size_t>(sizeof(T), value.size()));
    return out;
  }
};

// What the modify callback may change at unpack time. The resource layout is deliberately absent:
// the stored SPIR-V is bound to it, so it cannot change without recompiling. For a pipeline that
// uses an explicit render pass the attachment formats and sample count come from the render pass and
// must stay as they are.
struct PatchableState {
  // Render targets. A notation may leave them to run time (Diligent's Tutorial25 gives none: its
  // callback sets the count and the formats); after the callback, every location the pixel shader
  // writes needs a target, and a format that is not UNKNOWN, or the unpack fails naming the location.
  uint32_t color_count = 0;
  std::array<VkFormat, 8> color_formats{};
  // Read only, for the callback: bit i is set when the pixel shader writes render target i. A generic
  // callback can size color_count from it; changing it changes nothing.
  uint32_t written_color_targets = 0;
  VkFormat depth_stencil_format = VK_FORMAT_UNDEFINED;
  VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
  std::array<BlendAttachmentState, 8> blend{};
  RasterizerState rasterizer;
  DepthStencilState depth_stencil;
  // The pipeline's dynamic states: viewport and scissor always, blend constants and stencil reference by
  // default (as Diligent's Vulkan backend), and what the notation's `DynamicStates` adds. The callback may
  // add or remove any of Vulkan 1.0's and these of 1.3's extended dynamic state: cull mode, front face,
  // primitive topology, depth test/write enable, depth compare op, depth bounds test enable, stencil test
  // enable, stencil op. One the device lacks is an `unsupported` error naming it.
  std::vector<VkDynamicState> dynamic_states;
  // The pipeline's specialization constants (graphics and compute); the callback may change values.
  std::vector<SpecializationConstant> constants;

  // Sets a constant by name; false when there is none or sizeof(T) differs from its size (bool is
  // stored as a VkBool32).
  template <class T>
  bool set_constant(std::string_view name, T v) {
    if constexpr (std::is_same_v<T, bool>) return set_constant(name, uint32_t(v ? 1 : 0));
    for (auto& c : constants) {
      if (c.name != name) continue;
      if (c.size != sizeof(T)) return false;
      c.value = {};
      std::memcpy(c.value.data(), &v, sizeof(T));
      return true;
    }
    return false;
  }
  const SpecializationConstant* find_constant(std::string_view name) const {
    for (const auto& c : constants)
      if (c.name == name) return &c;
    return nullptr;
  }
};
// Called with a pipeline's archived state before the pipeline is created; what it leaves in the state
// is checked like the archive's own values, then used. It runs while the Dearchiver is locked: it must
// not call the Dearchiver. An exception it throws becomes an `invalid_argument` error naming the pipeline.
using ModifyCallback = std::function<void(PatchableState&)>;
// unpack_all's callback: the same, for every pipeline, told which one it patches (its name, and its
// kind: graphics_pipeline or compute_pipeline), so one callback can give every graphics pipeline the
// swapchain's format.
using PatchCallback = std::function<void(const ObjectInfo& pipeline, PatchableState&)>;

// One resource of a pipeline's layout, as the shaders name it.
struct BindingInfo {
  std::string name;
  uint32_t set = 0;
  uint32_t binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
  uint32_t count = 1;
  VkShaderStageFlags stages = 0;
  // The sampler baked into the set layout (the notation's immutable sampler), owned by the Dearchiver;
  // null when the application writes the sampler. Descriptor writes for such a binding give no sampler.
  VkSampler immutable_sampler = VK_NULL_HANDLE;
};

struct STATEPACK_API UnpackedPipeline {
  std::string name;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipelineBindPoint bind_point = VK_PIPELINE_BIND_POINT_GRAPHICS;
  std::vector<VkDescriptorSetLayout> set_layouts;  // index = set number
  std::vector<BindingInfo> bindings;
  uint32_t push_constant_size = 0;
  VkShaderStageFlags push_constant_stages = 0;

  const BindingInfo* find_binding(std::string_view resource_name) const;
};

// A resource signature: one descriptor set layout, shared by the pipelines that use it.
struct UnpackedSignature {
  std::string name;
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  uint32_t set = 0;  // the set number pipelines bind it at (DRSN BindingIndex)
  std::vector<BindingInfo> bindings;
};

// A standalone shader of the archive's Shaders section.
struct UnpackedShader {
  std::string name;
  VkShaderModule module = VK_NULL_HANDLE;
  VkShaderStageFlagBits stage = VK_SHADER_STAGE_VERTEX_BIT;
  std::string entry_point;
};

struct DeviceContext {
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  const VkAllocationCallbacks* allocator = nullptr;
  VkPipelineCache pipeline_cache = VK_NULL_HANDLE;
  // Graphics pipelines without render passes need dynamic rendering (Vulkan 1.3 core, or
  // VK_KHR_dynamic_rendering); say whether the device was created with the feature enabled.
  bool dynamic_rendering_enabled = true;
  // The core features the device was created with, to report pipelines that need others (geometry or
  // tessellation shaders, depth clamp, wireframe, dual-source or independent blending, anisotropy)
  // as errors. Null: assume every feature the device supports is enabled.
  const VkPhysicalDeviceFeatures* enabled_features = nullptr;
  // The pNext chain of features the device was created with (VkDeviceCreateInfo::pNext): a
  // VkPhysicalDeviceFeatures2 and/or VkPhysicalDeviceVulkan11/12/13Features and extension feature
  // structures. A shader declaring a SPIR-V capability that nothing in it enables (Int8 without
  // shaderInt8, MultiView without multiview, ...) is an `unsupported` error naming the features that
  // would allow it, before any Vulkan call. A structure missing from a given chain counts as all off.
  // Null: Vulkan 1.1-1.3 features are taken as the device supports them, extension structures as on.
  // Read during Dearchiver::create only.
  const void* enabled_feature_chain = nullptr;
  // The device extensions the device was created with, for capabilities an extension allows
  // (VK_KHR_shader_draw_parameters, ...). Null: taken as enabled.
  const char* const* enabled_extensions = nullptr;
  uint32_t enabled_extension_count = 0;
  // Where the Vulkan entry points come from: the application owns dispatch. Give the loader you use
  // (volk: `ctx.instance = instance; ctx.get_instance_proc_addr = vkGetInstanceProcAddr;` after
  // volkLoadInstance) and every function is looked up through it once, in Dearchiver::create, and
  // device functions through vkGetDeviceProcAddr. Null: the system loader, libvulkan.so.1, opened at
  // run time (the library links no loader either way). load_pipeline_cache and save_pipeline_cache
  // use the same fields.
  VkInstance instance = VK_NULL_HANDLE;  // needed with get_instance_proc_addr
  PFN_vkGetInstanceProcAddr get_instance_proc_addr = nullptr;
  PFN_vkGetDeviceProcAddr get_device_proc_addr = nullptr;  // optional: else from get_instance_proc_addr
};

class STATEPACK_API Dearchiver {
 public:
  static Result<Dearchiver> create(const DeviceContext& context);

  Dearchiver(Dearchiver&&) noexcept;
  Dearchiver& operator=(Dearchiver&&) noexcept;
  ~Dearchiver();  // destroys every Vulkan object it created

  // Adds an archive; names resolve across all added archives, the earliest added winning.
  Result<void> add_archive(Archive archive);

  // Unpacks a pipeline by name. The pointer stays valid until release() or the Dearchiver's end.
  // Unpacking the same name twice without a callback returns the same pipeline; with a callback, a
  // variant whose settled state (what the callback left: formats, blending, rasterizer, depth-stencil,
  // samples, dynamic states, constants) equals an earlier one's returns that one, whichever callback
  // made it, so repeated or alternating patches (swapchain recreation, MSAA toggles) make one
  // pipeline per distinct state.
  Result<const UnpackedPipeline*> unpack_graphics(std::string_view name, const ModifyCallback& modify = {});
  // For compute pipelines the callback may change `constants` only (the rest does not apply).
  Result<const UnpackedPipeline*> unpack_compute(std::string_view name, const ModifyCallback& modify = {});

  // Unpacks every pipeline of every added archive (the earliest archive wins a name), creating the
  // pipelines on `threads` threads (0: all cores), then every signature, render pass and standalone
  // shader. Returns the pipelines.
  Result<std::vector<const UnpackedPipeline*>> unpack_all(uint32_t threads = 0);
  // The same, with every pipeline's state first given to `patch` (once per pipeline, on the calling
  // thread, one after another, before any pipeline is created). A patched pipeline is reused when an
  // earlier patched unpack settled the same state (as with unpack_graphics(name, modify)), never
  // taken from the unpatched ones.
  // An empty `patch` is the call above.
  Result<std::vector<const UnpackedPipeline*>> unpack_all(const PatchCallback& patch, uint32_t threads = 0);

  // Unpack the other named objects. Each is created once and owned by the Dearchiver.
  Result<const UnpackedSignature*> unpack_signature(std::string_view name);
  Result<VkRenderPass> unpack_render_pass(std::string_view name);
  Result<UnpackedShader> unpack_shader(std::string_view name);

  std::vector<std::string> pipeline_names() const;

  // Destroys a pipeline (a variant or not) this Dearchiver unpacked: vkDestroyPipeline now, so the GPU
  // must be done with it, as for any VkPipeline. Its pointer, and every pointer to it that unpack
  // calls returned, is invalid after; a later unpack of the same name and state creates it again. The
  // layouts, set layouts and shader modules it used stay (shared, owned by the Dearchiver).
  // invalid_argument for a pointer this Dearchiver does not hold (released already, or not its own).
  Result<void> release(const UnpackedPipeline* pipeline);

 private:
  struct State;
  explicit Dearchiver(std::unique_ptr<State> state);
  Result<std::vector<const UnpackedPipeline*>> unpack_all_pipelines(uint32_t threads,
                                                                    const PatchCallback& patch);
  std::unique_ptr<State> state_;
};

// A VkPipelineCache restored from a file written by save_pipeline_cache. The file's own header
// (vendor, device, driver version and ID, pipeline-cache and device UUIDs, driver info, pointer size,
// data hash) is checked against the device first; on any mismatch the stale data is ignored, the cache
// starts empty, and `reason` says why. Needs Vulkan 1.2 for the driver fields (zero before).
struct PipelineCacheLoad {
  VkPipelineCache cache = VK_NULL_HANDLE;  // always created on success; the caller destroys it
  bool reused = false;                     // the saved data was handed to the driver
  std::string reason;                      // why not, when not
};
STATEPACK_API Result<PipelineCacheLoad> load_pipeline_cache(const DeviceContext& context,
                                                            const std::filesystem::path& path);
// Writes the cache's data behind that header, atomically (temporary file, then rename).
STATEPACK_API Result<void> save_pipeline_cache(const DeviceContext& context, VkPipelineCache cache,
                                               const std::filesystem::path& path);

}  // namespace statepack
