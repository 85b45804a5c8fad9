// libstatepack_dearchiver — unpacks statepack archives into Vulkan objects.
//
//   auto archive = statepack::Archive::from_file("scene.spk");          // or from_memory(bytes)
//   if (!archive) return fail(archive.error());                         // every call returns a Result
//   statepack::DeviceContext context{physical_device, device};
//   context.enabled_feature_chain = &enabled;  // what vkCreateDevice got: null means "nothing enabled"
//   auto dearchiver = statepack::Dearchiver::create(context);
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
#include <chrono>
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
  // Field by field: the bytes between the fields are nobody's (a copy need not carry them).
  bool operator==(const BlendAttachmentState&) const = default;
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

// How the driver's pipeline creation went, for a loading screen's log or a build step's report.
struct PipelineCreation {
  // Wall time of this pipeline's vkCreateGraphicsPipelines / vkCreateComputePipelines call.
  std::chrono::nanoseconds time{0};
  // VK_EXT_pipeline_creation_feedback (core in Vulkan 1.3), asked for when the device has it: whether the
  // driver filled it in, its own duration, and whether DeviceContext::pipeline_cache held the pipeline.
  bool feedback = false;
  std::chrono::nanoseconds driver_time{0};
  bool cache_hit = false;
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
  PipelineCreation creation;

  const BindingInfo* find_binding(std::string_view resource_name) const;
};

// A patched pipeline an application created, as a variants file records it (docs/variants.md): the
// pipeline's name and kind, and the fields of PatchableState its callback changed from the archived
// state, as a JSON object ({"color_formats.0": "VK_FORMAT_B8G8R8A8_SRGB"}). Dearchiver::variants()
// gives those it made; load_variants() reads a file; Dearchiver::unpack_variant() makes one again.
struct STATEPACK_API PipelineVariant {
  std::string pipeline;
  ObjectKind kind = ObjectKind::graphics_pipeline;
  std::string state;  // the JSON object of changed fields ("{}": none)
  // Where it was read, for messages: "variants file 'v.json' at /variants/2" (load_variants and
  // parse_variants set it); empty for Dearchiver::variants()' own.
  std::string origin;

  // Sets the recorded fields in `s` (a modify callback's state); invalid_argument naming the field for
  // one that is unknown or out of range (load_variants checks every field, so its variants apply).
  Result<void> apply(PatchableState& s) const;
};

// The variants of a file written by Dearchiver::save_variants (or by hand: docs/variants.md), each
// checked; an error names the file, the JSON pointer and the reason.
STATEPACK_API Result<std::vector<PipelineVariant>> load_variants(const std::filesystem::path& path);
// The same from text in memory; `name` is what messages call it.
STATEPACK_API Result<std::vector<PipelineVariant>> parse_variants(std::string_view json,
                                                                  std::string_view name);

// What unpack_all learns as it goes: called once per pipeline, after it is created or has failed.
struct UnpackProgress {
  const ObjectInfo* object = nullptr;          // the pipeline
  const UnpackedPipeline* pipeline = nullptr;  // null when it failed
  const Error* error = nullptr;                // null when it was created (or reused)
  size_t done = 0, total = 0;                  // pipelines finished so far (this one included), of all
};
// Called on whichever thread finished the pipeline, never two at once. It may call the job's non-waiting
// members (ready, done), release pipelines, and destroy the job or the Dearchiver (the job then ends);
// it must not wait for the job or unpack a pipeline the job has not finished: the thread that would make
// it may be this one.
using ProgressCallback = std::function<void(const UnpackProgress&)>;

struct UnpackAllOptions {
  PatchCallback patch;        // each pipeline's state, as unpack_all(patch, threads) does; empty: none
  ProgressCallback progress;  // empty: none
  uint32_t threads = 0;       // threads creating pipelines; 0: one per core
};

// A pipeline (or other object) unpack_all could not make, and why.
struct UnpackFailure {
  ObjectInfo object;
  Error error;
};

// Everything unpack_all did: every pipeline it returns, and every object that failed, in archive order.
struct UnpackReport {
  std::vector<const UnpackedPipeline*> pipelines;
  std::vector<UnpackFailure> failures;
  // Sum of the pipelines' PipelineCreation::time, and the wall time of the whole call.
  std::chrono::nanoseconds creation_time{0}, wall_time{0};
  bool ok() const { return failures.empty(); }
};

// What Dearchiver::reload did. The first four lists name the pipelines this Dearchiver had unpacked from
// the replaced archive (a pipeline with several patched variants once per variant).
struct ReloadReport {
  std::vector<std::string> recreated;   // changed: a new VkPipeline in the same UnpackedPipeline
  std::vector<std::string> kept;        // unchanged: the same VkPipeline
  std::vector<std::string> removed;     // gone from the archive: the pipeline stays until released
  std::vector<UnpackFailure> failures;  // changed but not re-created, and why: the old pipeline stays
  std::vector<std::string> added;       // pipelines the new archive has and the old one had not
  uint64_t generation = 0;              // reload_generation() after the call
  bool ok() const { return failures.empty(); }
};

struct ReloadOptions {
  size_t archive = 0;  // which added archive the new one replaces: 0 is the first add_archive gave
  // Called for each patched pipeline being re-created (not for unchanged ones), with the new archive's
  // state after the changes its callback made at unpack time were applied again (what variants()
  // records); it may change more. Empty: those changes alone. Unpatched pipelines are re-created unpatched.
  PatchCallback patch;
  // An archive whose content version differs from the replaced one's is refused unless this is set.
  bool allow_content_version_change = false;
};

// unpack_all_async's handle: pipelines are created on its own threads while the application goes on.
// Destroying it (or the Dearchiver) cancels the pipelines not yet begun and waits for those being
// created; the pipelines made stay the Dearchiver's.
class STATEPACK_API UnpackJob {
 public:
  UnpackJob(UnpackJob&&) noexcept;
  UnpackJob& operator=(UnpackJob&&) noexcept;
  ~UnpackJob();

  // Waits for that pipeline only (not for the others), then returns it or its error; not_found for a
  // name the job does not create.
  Result<const UnpackedPipeline*> wait(std::string_view name);
  // Whether that pipeline is finished (created or failed), without waiting.
  bool ready(std::string_view name) const;
  size_t done() const;   // pipelines finished
  size_t total() const;  // pipelines the job creates
  // Waits for every pipeline; the report holds every failure of the job, planning included.
  UnpackReport wait_all();

  struct Shared;  // the job's state, shared with its threads and the Dearchiver

 private:
  friend class Dearchiver;
  explicit UnpackJob(std::shared_ptr<Shared> shared);
  std::shared_ptr<Shared> shared_;
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
  // What the device was created with, so that a pipeline needing something else is an `unsupported`
  // error naming the feature before any Vulkan call, never a validation error. Null means what it
  // means to vkCreateDevice: nothing enabled. Pass what you gave VkDeviceCreateInfo.
  //
  // The core features (pEnabledFeatures, or the chain's VkPhysicalDeviceFeatures2): geometry or
  // tessellation shaders, depth clamp, wireframe, dual-source or independent blending, anisotropy and
  // the SPIR-V capabilities of Vulkan 1.0.
  const VkPhysicalDeviceFeatures* enabled_features = nullptr;
  // The pNext chain of features the device was created with (VkDeviceCreateInfo::pNext): a
  // VkPhysicalDeviceFeatures2 and/or VkPhysicalDeviceVulkan11/12/13Features and extension feature
  // structures. A shader declaring a SPIR-V capability that nothing in it enables (Int8 without
  // shaderInt8, MultiView without multiview, ...) is an `unsupported` error naming the features that
  // would allow it. A structure missing from the chain counts as all off. Read during
  // Dearchiver::create only.
  const void* enabled_feature_chain = nullptr;
  // The device extensions the device was created with, for capabilities an extension allows
  // (VK_KHR_shader_draw_parameters, ...) and VK_EXT_pipeline_creation_feedback before Vulkan 1.3.
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
  // The Vulkan version the instance was created for (VkApplicationInfo::apiVersion). What the library
  // may use is the lower of it and the device's version, as the spec (and the validation layer) has it:
  // an application asking for Vulkan 1.1 on a 1.3 device gets no 1.2 structure in its calls. 0: the
  // device's version (right when the instance asked for at least that much).
  uint32_t api_version = 0;
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
  // shader. Returns the pipelines; when any object fails, the others are still made and the error lists
  // every failure (the first one's code). unpack_all(options) returns them one by one instead.
  Result<std::vector<const UnpackedPipeline*>> unpack_all(uint32_t threads = 0);
  // The same, with every pipeline's state first given to `patch` (once per pipeline, on the calling
  // thread, one after another, before any pipeline is created). A patched pipeline is reused when an
  // earlier patched unpack settled the same state (as with unpack_graphics(name, modify)), never
  // taken from the unpatched ones.
  // An empty `patch` is the call above.
  Result<std::vector<const UnpackedPipeline*>> unpack_all(const PatchCallback& patch, uint32_t threads = 0);
  // The same with a progress callback; every failure is in the report, not an error (an error is
  // returned only for what stops the whole call, such as out_of_memory).
  Result<UnpackReport> unpack_all(const UnpackAllOptions& options);
  // The same without waiting: the states are patched and the shared objects made on the calling
  // thread, then the call returns while the job's threads create the pipelines (options.threads, 0: one
  // per core). UnpackJob::wait(name) waits for one of them; unpack_graphics/unpack_compute of a pipeline
  // the job is creating (unpatched: the same pipeline) waits for that one too.
  Result<UnpackJob> unpack_all_async(UnpackAllOptions options = {});

  // The patched variants this Dearchiver created (each distinct settled state once, in the order they
  // were first made, released ones included), and the same written as a variants file, atomically:
  // `statepack verify ARCHIVE --variants FILE --cache OUT` creates exactly these to warm a cache.
  std::vector<PipelineVariant> variants() const;
  Result<void> save_variants(const std::filesystem::path& path) const;
  // Unpacks a recorded variant: its pipeline, patched by PipelineVariant::apply.
  Result<const UnpackedPipeline*> unpack_variant(const PipelineVariant& variant);

  // Replaces an added archive with a new build of it, for a development loop (docs/api.md, "Reloading
  // while the application runs"). Every pipeline unpacked from the old archive is compared with its
  // namesake in the new one by content (shaders' SPIR-V, state, layouts, render pass, constants): an
  // unchanged one keeps its VkPipeline; a changed one is re-created, patched as it was (its recorded
  // changes, then options.patch), and its new VkPipeline is written into the same UnpackedPipeline, so
  // every pointer the application holds stays valid and reads the new pipeline. The old VkPipeline is
  // retired, not destroyed: the GPU may still use it (destroy_retired). A change no reload can apply in
  // place (the pipeline layout, which descriptor sets were made for, or the render targets, which
  // attachments were made for) is a `layout_changed` failure in the report naming the pipeline and the
  // change; any failure keeps the old pipeline. BindingInfo pointers stay valid (names may change). Later
  // unpacks by name use the new archive. Waits for running unpack jobs first (never call it from their
  // callbacks). Call it where the application does not read the pipelines meanwhile, e.g. between frames on
  // the thread that records commands. An error is returned for what stops the whole reload (a wrong index,
  // another content version); the archive is then not used.
  Result<ReloadReport> reload(Archive archive, const ReloadOptions& options = {});
  // How many reloads re-created a pipeline: a renderer that copies VkPipeline handles re-reads them
  // when it changes (pointers to UnpackedPipeline always read the current one).
  uint64_t reload_generation() const;
  // Destroys the VkPipelines that reloads up to `through_generation` replaced (all by default), once the
  // application knows the GPU is done with them (a fence of the frames recorded before the reload, or
  // vkDeviceWaitIdle). Returns how many it destroyed. The Dearchiver's destructor destroys the rest.
  size_t destroy_retired(uint64_t through_generation = UINT64_MAX);

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

  struct State;  // internal (runtime/dearchiver_state.hpp)

 private:
  explicit Dearchiver(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

// Tells a running application that a new build of an archive file was written completely, without a
// shader compiler: pair it with `statepack pack --watch` and Dearchiver::reload (docs/api.md). poll() is
// cheap enough for every frame: one stat() of the file when it did not change.
class STATEPACK_API ArchiveFileWatch {
 public:
  // Watches `path`; what it holds now counts as what the application has loaded.
  static Result<ArchiveFileWatch> create(std::filesystem::path path,
                                         std::optional<uint32_t> required_content_version = std::nullopt);

  ArchiveFileWatch(ArchiveFileWatch&&) noexcept;
  ArchiveFileWatch& operator=(ArchiveFileWatch&&) noexcept;
  ~ArchiveFileWatch();

  // A new archive when the file changed since the last look and now holds a complete, valid archive
  // whose bytes differ from the last one handed back (or the one there at create); nullopt when there is
  // nothing new: unchanged, the same bytes written again, missing for now (an editor or packer replacing
  // it), or still being written (shorter than its header says). An error, once per change of the file,
  // for a complete file that is not a valid archive (another content version, corrupt); the next change
  // is looked at again.
  Result<std::optional<Archive>> poll();
  const std::filesystem::path& path() const;

 private:
  struct State;
  explicit ArchiveFileWatch(std::unique_ptr<State> state);
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
