#include "renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace statepack::path_tracer {
namespace {

using bootstrap::image_barrier;

// std140 layout of `Constants` in shaders/path_tracer/scene.glsl.
struct Constants {
  float camera_position[4], camera_right[4], camera_up[4], camera_forward[4];
  uint32_t frame[4];  // samples before this batch, samples in it, bounces, flags
  uint32_t image[4];  // width, height, seed, box count
  uint32_t light[4];  // light box index, first bounce of Russian roulette, divisor, full width | height << 16
  uint32_t lights[4];  // first record of the lights without area (after the boxes), their count
};
static_assert(sizeof(Constants) == 128);

Error vk_error(const char* call, VkResult r) {
  return Error{ErrorCode::vulkan_error, std::string(call) + " failed with VkResult " + std::to_string(r), r};
}

}  // namespace

Result<std::unique_ptr<Renderer>> Renderer::create(bootstrap::VulkanContext& vk, Dearchiver& dearchiver,
                                                   uint32_t width, uint32_t height, VkFormat target_format) {
  if (width > 0xFFFF || height > 0xFFFF)  // Constants carry the full size in 16 bits each
    return Error{ErrorCode::invalid_argument, "an image of " + std::to_string(width) + "x" +
                                                  std::to_string(height) +
                                                  " is larger than the path tracer's 65535"};
  std::unique_ptr<Renderer> r(new Renderer(vk));
  r->dearchiver_ = &dearchiver;
  r->width_ = width;
  r->height_ = height;
  r->target_format_ = target_format;
  auto gbuffer = dearchiver.unpack_graphics("G-Buffer PSO");
  if (!gbuffer) return gbuffer.error();
  auto trace = dearchiver.unpack_compute("Path Trace PSO");
  if (!trace) return trace.error();
  auto trace_mis = dearchiver.unpack_compute("Path Trace MIS PSO");
  if (!trace_mis) return trace_mis.error();
  auto trace_baseline = dearchiver.unpack_compute("Path Trace Baseline PSO");
  if (!trace_baseline) return trace_baseline.error();
  // The variants differ only in code: one descriptor set serves them all.
  for (const UnpackedPipeline* variant : {*trace_mis, *trace_baseline})
    if (variant->layout != (*trace)->layout)
      return Error{ErrorCode::invalid_argument, "the path-tracing variants must share one pipeline layout"};
  // The resolve target's format is known only now (a swapchain's, or the offscreen image's).
  auto resolve = dearchiver.unpack_graphics("Resolve PSO",
                                            [&](PatchableState& s) { s.color_formats[0] = target_format; });
  if (!resolve) return resolve.error();
  r->gbuffer_ = *gbuffer;
  r->trace_ = *trace;
  r->trace_mis_ = *trace_mis;
  r->trace_baseline_ = *trace_baseline;
  r->resolve_ = *resolve;

  auto constants = bootstrap::create_host_buffer(vk, sizeof(Constants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  if (!constants) return constants.error();
  r->constants_ = std::move(constants.value());

  VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 2},
                                  {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2},
                                  {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 6}};
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.maxSets = 3;
  pool_info.poolSizeCount = 3;
  pool_info.pPoolSizes = sizes;
  if (VkResult res = vkCreateDescriptorPool(vk.device, &pool_info, nullptr, &r->pool_); res != VK_SUCCESS)
    return vk_error("vkCreateDescriptorPool", res);
  VkDescriptorSetLayout layouts[] = {r->gbuffer_->set_layouts.at(0), r->trace_->set_layouts.at(0),
                                     r->resolve_->set_layouts.at(0)};
  VkDescriptorSet sets[3];
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = r->pool_;
  alloc.descriptorSetCount = 3;
  alloc.pSetLayouts = layouts;
  if (VkResult res = vkAllocateDescriptorSets(vk.device, &alloc, sets); res != VK_SUCCESS)
    return vk_error("vkAllocateDescriptorSets", res);
  r->gbuffer_set_ = sets[0], r->trace_set_ = sets[1], r->resolve_set_ = sets[2];
  if (auto images = r->create_images(); !images) return images.error();
  VkQueryPoolCreateInfo query{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  query.queryType = VK_QUERY_TYPE_TIMESTAMP;
  query.queryCount = 2;
  if (VkResult res = vkCreateQueryPool(vk.device, &query, nullptr, &r->timestamps_); res != VK_SUCCESS)
    return vk_error("vkCreateQueryPool", res);
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(vk.physical_device, &props);
  r->timestamp_period_ns_ = props.limits.timestampPeriod;
  return r;
}

Renderer::~Renderer() {
  vkDeviceWaitIdle(vk_.device);
  destroy_images();
  if (pool_) vkDestroyDescriptorPool(vk_.device, pool_, nullptr);
  if (timestamps_) vkDestroyQueryPool(vk_.device, timestamps_, nullptr);
}

double Renderer::last_trace_ms() const {
  uint64_t ticks[2] = {};
  if (vkGetQueryPoolResults(vk_.device, timestamps_, 0, 2, sizeof ticks, ticks, sizeof(uint64_t),
                            VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
    return 0;
  return double(ticks[1] - ticks[0]) * timestamp_period_ns_ * 1e-6;
}

Result<void> Renderer::create_images() {
  const VkImageUsageFlags gbuffer_usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
  struct Wanted {
    Image* image;
    VkFormat format;
    VkImageUsageFlags usage;
  };
  for (auto [image, format, usage] : {Wanted{&albedo_, VK_FORMAT_R32G32B32A32_SFLOAT, gbuffer_usage},
                                      Wanted{&normal_, VK_FORMAT_R32G32B32A32_SFLOAT, gbuffer_usage},
                                      Wanted{&emittance_, VK_FORMAT_R32G32B32A32_SFLOAT, gbuffer_usage},
                                      Wanted{&depth_, VK_FORMAT_R32_SFLOAT, gbuffer_usage},
                                      Wanted{&accumulation_, VK_FORMAT_R32G32B32A32_SFLOAT,
                                             VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT}}) {
    auto created = bootstrap::create_device_image(vk_, format, width_, height_, usage);
    if (!created) return created.error();
    *image = std::move(created.value());
  }
  // The accumulation image lives in GENERAL; the G-buffer is moved there after each render.
  auto done = vk_.submit_and_wait([&](VkCommandBuffer cmd) {
    for (Image* image : {&albedo_, &normal_, &emittance_, &depth_, &accumulation_})
      image_barrier(cmd, (*image)->image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, 0,
                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT);
  });
  if (!done) return done.error();
  write_descriptors();
  restart();
  return {};
}

void Renderer::destroy_images() {
  for (Image* image : {&albedo_, &normal_, &emittance_, &depth_, &accumulation_}) image->reset();
}

Result<void> Renderer::resize(uint32_t width, uint32_t height) {
  if (width > 0xFFFF || height > 0xFFFF)
    return Error{ErrorCode::invalid_argument, "an image of " + std::to_string(width) + "x" +
                                                  std::to_string(height) +
                                                  " is larger than the path tracer's 65535"};
  vkDeviceWaitIdle(vk_.device);
  destroy_images();
  width_ = width, height_ = height;
  auto created = create_images();
  if (created && boxes_) write_descriptors();
  return created;
}

void Renderer::write_descriptors() {
  std::vector<VkWriteDescriptorSet> writes;
  std::vector<std::unique_ptr<VkDescriptorBufferInfo>> buffers;
  std::vector<std::unique_ptr<VkDescriptorImageInfo>> images;
  auto bind = [&](VkDescriptorSet set, const UnpackedPipeline* pso, const char* name, VkBuffer buffer,
                  VkImageView view) {
    const BindingInfo* b = pso->find_binding(name);
    if (!b || (buffer == VK_NULL_HANDLE && view == VK_NULL_HANDLE)) return;  // unused by that shader
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.dstBinding = b->binding;
    w.descriptorCount = 1;
    w.descriptorType = b->type;
    if (buffer) {
      buffers.push_back(
          std::make_unique<VkDescriptorBufferInfo>(VkDescriptorBufferInfo{buffer, 0, VK_WHOLE_SIZE}));
      w.pBufferInfo = buffers.back().get();
    } else {
      images.push_back(std::make_unique<VkDescriptorImageInfo>(
          VkDescriptorImageInfo{VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL}));
      w.pImageInfo = images.back().get();
    }
    writes.push_back(w);
  };
  VkBuffer scene_buffer = boxes_ ? boxes_->buffer : VK_NULL_HANDLE;
  for (auto [set, pso] : {std::pair{gbuffer_set_, gbuffer_}, std::pair{trace_set_, trace_}}) {
    bind(set, pso, "Constants", constants_->buffer, VK_NULL_HANDLE);
    bind(set, pso, "Scene", scene_buffer, VK_NULL_HANDLE);
  }
  bind(trace_set_, trace_, "g_albedo", VK_NULL_HANDLE, albedo_->view);
  bind(trace_set_, trace_, "g_normal", VK_NULL_HANDLE, normal_->view);
  bind(trace_set_, trace_, "g_emittance", VK_NULL_HANDLE, emittance_->view);
  bind(trace_set_, trace_, "g_depth", VK_NULL_HANDLE, depth_->view);
  bind(trace_set_, trace_, "accumulation", VK_NULL_HANDLE, accumulation_->view);
  bind(resolve_set_, resolve_, "accumulation", VK_NULL_HANDLE, accumulation_->view);
  vkUpdateDescriptorSets(vk_.device, static_cast<uint32_t>(writes.size()), writes.data(), 0, nullptr);
}

Result<void> Renderer::set_scene(const Scene& scene) {
  if (auto ok = specialize(scene); !ok) return ok;
  scene_ = scene;
  upload_scene();
  restart();
  return {};
}

// The path-tracing pipelines for the scene's lights: the rectangle's code only when it has one, and
// the code of each kind of light without area only when it has that kind (specialization constants;
// the dearchiver keeps one pipeline per settled state, so switching back costs nothing).
Result<void> Renderer::specialize(const Scene& scene) {
  const bool area = scene.area_light;
  const uint32_t kinds = light_kinds(scene);
  const UnpackedPipeline* made[3] = {};
  const char* names[3] = {"Path Trace PSO", "Path Trace MIS PSO", "Path Trace Baseline PSO"};
  for (int i = 0; i < 3; ++i) {
    std::string missing;
    auto pso = dearchiver_->unpack_compute(names[i], [&](PatchableState& s) {
      if (!s.set_constant("kAreaLight", area)) missing = "kAreaLight";
      if (!s.set_constant("kLightKinds", kinds)) missing = "kLightKinds";
    });
    if (!pso) return pso.error();
    if (!missing.empty())
      return Error{ErrorCode::invalid_argument, std::string("pipeline '") + names[i] +
                                                    "' has no 4-byte specialization constant '" + missing +
                                                    "' (the archive is older than this path tracer)"};
    if ((*pso)->layout != trace_->layout)
      return Error{ErrorCode::invalid_argument, "the path-tracing variants must share one pipeline layout"};
    made[i] = *pso;
  }
  trace_ = made[0], trace_mis_ = made[1], trace_baseline_ = made[2];
  return {};
}

void Renderer::upload_scene() {
  std::vector<GpuBox> boxes = gpu_boxes(scene_, light_index_);
  box_count_ = static_cast<uint32_t>(boxes.size());
  const std::vector<GpuBox> lights = gpu_lights(scene_);
  light_count_ = static_cast<uint32_t>(lights.size());
  boxes.insert(boxes.end(), lights.begin(), lights.end());  // after the boxes: traced as boxes never
  other_emitters_ = std::any_of(scene_.boxes.begin(), scene_.boxes.end(), [](const SceneBox& b) {
    return b.emittance[0] > 0 || b.emittance[1] > 0 || b.emittance[2] > 0;
  });
  const VkDeviceSize size = boxes.size() * sizeof(GpuBox);
  if (!boxes_ || boxes_->size < size) {
    vkDeviceWaitIdle(vk_.device);
    auto created = bootstrap::create_host_buffer(vk_, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    if (!created) return;
    boxes_ = std::move(created.value());
    write_descriptors();
  }
  std::memcpy(boxes_->mapped, boxes.data(), size);
}

void Renderer::set_render_divisor(uint32_t divisor) {
  divisor = std::clamp(divisor, 1u, 8u);
  if (divisor == divisor_) return;
  divisor_ = divisor;
  restart();
}

void Renderer::set_camera(const Camera& camera) {
  scene_.camera = camera;
  restart();
}

void Renderer::set_settings(const RenderSettings& settings) {
  // Exposure and batch size do not change what converges (the mean is weighted by batch size).
  // Every other setting does.
  RenderSettings compared = settings;
  compared.exposure = settings_.exposure;
  compared.samples_per_frame = settings_.samples_per_frame;
  const bool same_estimate = compared == settings_;
  settings_ = settings;
  if (!same_estimate) samples_done_ = 0;  // the G-buffer does not depend on these
}

// Per-frame constants (one frame in flight: the previous frame has finished reading them).
void Renderer::write_constants() {
  const Camera& cam = scene_.camera;
  const uint32_t render_w = render_width(), render_h = render_height();  // traced: 1/divisor_ of the size
  const CameraBasis basis = camera_basis(cam, width_, height_);
  Constants c{};
  for (int i = 0; i < 3; ++i) {
    c.camera_position[i] = cam.position[i];
    c.camera_right[i] = static_cast<float>(basis.right[i]);
    c.camera_up[i] = static_cast<float>(basis.up[i]);
    c.camera_forward[i] = static_cast<float>(basis.forward[i]);
  }
  const RenderSettings& s = settings_;
  c.frame[0] = samples_done_;
  c.frame[1] = s.samples_per_frame;
  c.frame[2] = s.bounces;
  c.frame[3] = (s.next_event_estimation ? 1u : 0u) | (s.last_bounce_only ? 2u : 0u) |
               (other_emitters_ ? 4u : 0u) | (s.sampler == Sampler::sobol ? 8u : 0u) |
               (s.light_sampling == LightSampling::solid_angle ? 16u : 0u) |
               (s.delta_lights == DeltaLights::one ? 32u : 0u);
  c.image[0] = render_w, c.image[1] = render_h, c.image[2] = s.seed, c.image[3] = box_count_;
  c.light[0] = light_index_;
  c.light[1] = s.roulette_start;
  c.light[2] = divisor_;
  c.light[3] = width_ | height_ << 16;
  c.lights[0] = box_count_, c.lights[1] = light_count_;
  std::memcpy(constants_->mapped, &c, sizeof c);
}

void Renderer::record(VkCommandBuffer cmd, VkImage target, VkImageView target_view,
                      VkImageLayout final_layout) {
  write_constants();
  const uint32_t render_w = render_width(), render_h = render_height();  // traced: 1/divisor_ of the size
  const RenderSettings& s = settings_;

  const VkViewport viewport{0, 0, float(width_), float(height_), 0, 1};
  const VkRect2D area{{0, 0}, {width_, height_}};
  const VkViewport traced_viewport{0, 0, float(render_w), float(render_h), 0, 1};
  const VkRect2D traced_area{{0, 0}, {render_w, render_h}};
  if (gbuffer_dirty_) {
    VkRenderingAttachmentInfo attachments[4];
    Image* targets[] = {&albedo_, &normal_, &emittance_, &depth_};
    for (int i = 0; i < 4; ++i) {
      image_barrier(cmd, (*targets[i])->image, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_ACCESS_SHADER_READ_BIT,
                    VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                    VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
      attachments[i] = {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
      attachments[i].imageView = (*targets[i])->view;
      attachments[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
      attachments[i].loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;  // every pixel is written
      attachments[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    }
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = traced_area;  // the top left corner of the targets when traced smaller
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 4;
    rendering.pColorAttachments = attachments;
    vkCmdBeginRendering(cmd, &rendering);
    vkCmdSetViewport(cmd, 0, 1, &traced_viewport);
    vkCmdSetScissor(cmd, 0, 1, &traced_area);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gbuffer_->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gbuffer_->layout, 0, 1, &gbuffer_set_, 0,
                            nullptr);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
    for (Image* t : targets)
      image_barrier(cmd, (*t)->image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                    VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT,
                    VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
    gbuffer_dirty_ = false;
  }

  // The previous batch and resolve are done with the accumulation image before this batch writes it.
  image_barrier(cmd, accumulation_->image, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                    VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  const UnpackedPipeline* trace = s.estimator == Estimator::mis        ? trace_mis_
                                  : s.estimator == Estimator::baseline ? trace_baseline_
                                                                       : trace_;
  vkCmdResetQueryPool(cmd, timestamps_, 0, 2);
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timestamps_, 0);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, trace->pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, trace_->layout, 0, 1, &trace_set_, 0, nullptr);
  vkCmdDispatch(cmd, (render_w + 7) / 8, (render_h + 7) / 8, 1);
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps_, 1);
  samples_done_ += s.samples_per_frame;
  image_barrier(cmd, accumulation_->image, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT);

  image_barrier(cmd, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, 0,
                VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
  VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  color.imageView = target_view;
  color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
  rendering.renderArea = area;
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = 1;
  rendering.pColorAttachments = &color;
  vkCmdBeginRendering(cmd, &rendering);
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &area);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, resolve_->pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, resolve_->layout, 0, 1, &resolve_set_, 0,
                          nullptr);
  struct {
    float exposure;
    uint32_t divisor;
  } params{s.exposure, divisor_};  // resolve.frag's Params
  vkCmdPushConstants(cmd, resolve_->layout, resolve_->push_constant_stages, 0, sizeof params, &params);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
  const bool to_transfer = final_layout == VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  image_barrier(cmd, target, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, final_layout,
                VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, to_transfer ? VK_ACCESS_TRANSFER_READ_BIT : 0,
                VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                to_transfer ? VK_PIPELINE_STAGE_TRANSFER_BIT : VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
}

Result<std::vector<float>> Renderer::read_accumulation() {
  const VkDeviceSize size = VkDeviceSize(width_) * height_ * 4 * sizeof(float);
  auto readback = bootstrap::create_host_buffer(vk_, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
  if (!readback) return readback.error();
  auto done = vk_.submit_and_wait([&](VkCommandBuffer cmd) {
    image_barrier(cmd, accumulation_->image, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {width_, height_, 1};
    vkCmdCopyImageToBuffer(cmd, accumulation_->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           (*readback)->buffer, 1, &copy);
    image_barrier(cmd, accumulation_->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                  VK_ACCESS_TRANSFER_READ_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
  });
  if (!done) return done.error();
  const auto* data = static_cast<const float*>((*readback)->mapped);
  return std::vector<float>(data, data + size / sizeof(float));
}

}  // namespace statepack::path_tracer
