// Windowed path tracer: GLFW window and swapchain (the resolve pipeline is patched to the swapchain's
// format), first-person camera (left mouse button + WASDQE), light moved with the right mouse button,
// and a Dear ImGui panel. One frame in flight.
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui/backends/imgui_impl_glfw.h>
#include <imgui/backends/imgui_impl_vulkan.h>
#include <imgui/imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "app.hpp"
#include "frame_pacing.hpp"
#include "image_io.hpp"
#include "live_reload.hpp"

namespace statepack::path_tracer {
namespace {

struct Swapchain {
  VkSwapchainKHR handle = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkExtent2D extent{};
  std::vector<VkImage> images;
  std::vector<VkImageView> views;
  std::vector<VkFramebuffer> framebuffers;  // for the ImGui overlay's render pass
};

class Window {
 public:
  ~Window() { destroy(); }

  int run(const Options& o) {
    if (!o.screenshot.empty())
      if (std::string refused = bootstrap::output_refusal(o.screenshot, {o.scene, o.archive});
          !refused.empty())
        return fail("--screenshot: " + refused), 2;
    if (!glfwInit()) return fail("cannot initialise GLFW (no display?)");
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    window_ = glfwCreateWindow(int(o.width), int(o.height), "statepack path tracer", nullptr, nullptr);
    if (!window_) return fail("cannot create a window");
    uint32_t count = 0;
    const char** extensions = glfwGetRequiredInstanceExtensions(&count);
    if (!extensions) return fail("GLFW finds no Vulkan surface support");
    bootstrap::VulkanContextOptions vk_options;
    vk_options.validation = o.validation;
    vk_options.instance_extensions.assign(extensions, extensions + count);
    auto vk = bootstrap::VulkanContext::create(vk_options);
    if (!vk) return fail(vk.error().message);
    vk_ = std::move(vk.value());
    if (glfwCreateWindowSurface(vk_->instance, window_, nullptr, &surface_) != VK_SUCCESS)
      return fail("cannot create a window surface");
    VkBool32 present = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(vk_->physical_device, vk_->queue_family, surface_, &present);
    if (!present) return fail("the device's queue cannot present to this window");
    if (!create_swapchain()) return 1;

    auto scene = load_scene(o.scene);
    if (!scene) return fail(scene.error().message);
    dearchiver_ = load_archive(*vk_, o.archive);
    if (!dearchiver_) return 1;
    auto renderer = Renderer::create(*vk_, *dearchiver_, swapchain_.extent.width, swapchain_.extent.height,
                                     swapchain_.format);
    if (!renderer) return fail(renderer.error().message);
    renderer_ = std::move(renderer.value());
    if (auto ok = renderer_->set_scene(*scene); !ok) return fail(ok.error().message);
    renderer_->set_settings(o.settings);
    if (!create_sync() || !init_imgui()) return 1;
    std::unique_ptr<LiveReload> live = o.watch ? LiveReload::start(o.archive) : nullptr;
    if (o.watch && !live) return 1;

    uint32_t frames = 0;
    // Time between frames, for the report that --frames prints: of frames that moved, and of still ones.
    std::vector<float> moving_ms, still_ms;
    uint32_t moving_divisor = 1;  // the divisor moving frames were last traced at
    bool last_moved = false;
    auto last = std::chrono::steady_clock::now();
    while (!glfwWindowShouldClose(window_) && (o.frames == 0 || frames < o.frames)) {
      glfwPollEvents();
      if (live && live->poll(*dearchiver_, vk_->device)) renderer_->restart_accumulation();
      auto now = std::chrono::steady_clock::now();
      const float dt = std::chrono::duration<float>(now - last).count();
      last = now;
      if (frames > 0) (last_moved ? moving_ms : still_ms).push_back(dt * 1000.0f);
      moving_ = handle_input(dt);
      if (frames < o.move_frames) moving_ = turn_camera();  // --move-frames: a moving view, scripted
      last_moved = moving_;
      // With --frames and --screenshot, the last frame is also copied out of the swapchain.
      const bool capture = !o.screenshot.empty() && o.frames != 0 && frames + 1 == o.frames;
      if (!draw_frame(dt, capture)) return 1;
      if (moving_) moving_divisor = renderer_->render_divisor();
      ++frames;
    }
    vkDeviceWaitIdle(vk_->device);
    if (o.frames != 0) report_frames(frames, moving_ms, still_ms, moving_divisor);
    if (!o.screenshot.empty()) {
      if (screenshot_.empty())
        return fail("no screenshot taken (use --frames N, and a swapchain that allows copies)");
      if (auto error = write_rgba8(o.screenshot, screenshot_, swapchain_.extent.width,
                                   swapchain_.extent.height, {o.scene, o.archive});
          !error.empty())
        return fail(o.screenshot + ": " + error);
      std::printf("path_tracer: %u frames, %u spp, window screenshot -> %s\n", frames,
                  renderer_->samples_done(), printable(o.screenshot).c_str());
    }
    destroy();
    return validation_failures_ > 0 ? 1 : 0;
  }

 private:
  int fail(const std::string& message) {
    std::fprintf(stderr, "path_tracer: %s\n", printable(message).c_str());
    return 1;
  }

  bool create_swapchain() {
    VkSurfaceCapabilitiesKHR caps;
    vkGetPhysicalDeviceSurfaceCapabilitiesKHR(vk_->physical_device, surface_, &caps);
    uint32_t count = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(vk_->physical_device, surface_, &count, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(count);
    vkGetPhysicalDeviceSurfaceFormatsKHR(vk_->physical_device, surface_, &count, formats.data());
    VkSurfaceFormatKHR chosen = formats.at(0);
    for (const auto& f : formats)  // sRGB targets encode the linear radiance the resolve writes
      if ((f.format == VK_FORMAT_B8G8R8A8_SRGB || f.format == VK_FORMAT_R8G8B8A8_SRGB) &&
          f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
        chosen = f;
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    VkExtent2D extent =
        caps.currentExtent.width != UINT32_MAX ? caps.currentExtent : VkExtent2D{uint32_t(w), uint32_t(h)};
    extent.width =
        std::clamp(extent.width, std::max(caps.minImageExtent.width, 8u), caps.maxImageExtent.width);
    extent.height =
        std::clamp(extent.height, std::max(caps.minImageExtent.height, 8u), caps.maxImageExtent.height);
    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface_;
    info.minImageCount = std::max(caps.minImageCount, 2u);
    if (caps.maxImageCount) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
    info.imageFormat = chosen.format;
    info.imageColorSpace = chosen.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    can_capture_ = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;
    if (can_capture_) info.imageUsage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;  // for --screenshot
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    info.presentMode = VK_PRESENT_MODE_FIFO_KHR;
    info.clipped = VK_TRUE;
    info.oldSwapchain = swapchain_.handle;
    VkSwapchainKHR handle = VK_NULL_HANDLE;
    if (vkCreateSwapchainKHR(vk_->device, &info, nullptr, &handle) != VK_SUCCESS) {
      fail("cannot create the swapchain");
      return false;
    }
    destroy_swapchain_views();
    if (swapchain_.handle) vkDestroySwapchainKHR(vk_->device, swapchain_.handle, nullptr);
    swapchain_.handle = handle;
    swapchain_.format = chosen.format;
    swapchain_.extent = extent;
    vkGetSwapchainImagesKHR(vk_->device, handle, &count, nullptr);
    swapchain_.images.resize(count);
    vkGetSwapchainImagesKHR(vk_->device, handle, &count, swapchain_.images.data());
    for (VkImage image : swapchain_.images) {
      VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
      view.image = image;
      view.viewType = VK_IMAGE_VIEW_TYPE_2D;
      view.format = chosen.format;
      view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
      vkCreateImageView(vk_->device, &view, nullptr, &swapchain_.views.emplace_back());
    }
    return create_overlay_targets();
  }

  // ImGui 1.86 draws inside a render pass: one that loads the path-traced frame and presents.
  bool create_overlay_targets() {
    if (!overlay_pass_) {
      VkAttachmentDescription color{0,
                                    swapchain_.format,
                                    VK_SAMPLE_COUNT_1_BIT,
                                    VK_ATTACHMENT_LOAD_OP_LOAD,
                                    VK_ATTACHMENT_STORE_OP_STORE,
                                    VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                                    VK_ATTACHMENT_STORE_OP_DONT_CARE,
                                    VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                    VK_IMAGE_LAYOUT_PRESENT_SRC_KHR};
      VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
      VkSubpassDescription subpass{};
      subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
      subpass.colorAttachmentCount = 1;
      subpass.pColorAttachments = &ref;
      VkSubpassDependency dependency{
          VK_SUBPASS_EXTERNAL,
          0,
          VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
          VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
          VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
          VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
          0};
      VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
      info.attachmentCount = 1;
      info.pAttachments = &color;
      info.subpassCount = 1;
      info.pSubpasses = &subpass;
      info.dependencyCount = 1;
      info.pDependencies = &dependency;
      if (vkCreateRenderPass(vk_->device, &info, nullptr, &overlay_pass_) != VK_SUCCESS) {
        fail("cannot create the overlay render pass");
        return false;
      }
    }
    for (VkImageView view : swapchain_.views) {
      VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
      info.renderPass = overlay_pass_;
      info.attachmentCount = 1;
      info.pAttachments = &view;
      info.width = swapchain_.extent.width;
      info.height = swapchain_.extent.height;
      info.layers = 1;
      vkCreateFramebuffer(vk_->device, &info, nullptr, &swapchain_.framebuffers.emplace_back());
    }
    return true;
  }

  void destroy_swapchain_views() {
    for (auto fb : swapchain_.framebuffers) vkDestroyFramebuffer(vk_->device, fb, nullptr);
    for (auto view : swapchain_.views) vkDestroyImageView(vk_->device, view, nullptr);
    swapchain_.framebuffers.clear();
    swapchain_.views.clear();
    swapchain_.images.clear();
  }

  bool recreate_swapchain() {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    while ((w == 0 || h == 0) && !glfwWindowShouldClose(window_)) {  // minimised: wait
      glfwWaitEvents();
      glfwGetFramebufferSize(window_, &w, &h);
    }
    vkDeviceWaitIdle(vk_->device);
    if (!create_swapchain()) return false;
    ImGui_ImplVulkan_SetMinImageCount(2);
    auto resized = renderer_->resize(swapchain_.extent.width, swapchain_.extent.height);
    if (!resized) fail(resized.error().message);
    return bool(resized);
  }

  bool create_sync() {
    VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = vk_->command_pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    return vkCreateSemaphore(vk_->device, &semaphore, nullptr, &acquired_) == VK_SUCCESS &&
           vkCreateSemaphore(vk_->device, &semaphore, nullptr, &rendered_) == VK_SUCCESS &&
           vkCreateFence(vk_->device, &fence, nullptr, &in_flight_) == VK_SUCCESS &&
           vkAllocateCommandBuffers(vk_->device, &alloc, &cmd_) == VK_SUCCESS;
  }

  bool init_imgui() {
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 8};
    VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pool.maxSets = 8;
    pool.poolSizeCount = 1;
    pool.pPoolSizes = &size;
    vkCreateDescriptorPool(vk_->device, &pool, nullptr, &imgui_pool_);
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the user's directory
    ImGui_ImplGlfw_InitForVulkan(window_, true);
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = vk_->instance;
    info.PhysicalDevice = vk_->physical_device;
    info.Device = vk_->device;
    info.QueueFamily = vk_->queue_family;
    info.Queue = vk_->queue;
    info.DescriptorPool = imgui_pool_;
    info.MinImageCount = 2;
    info.ImageCount = static_cast<uint32_t>(swapchain_.images.size());
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    if (!ImGui_ImplVulkan_Init(&info, overlay_pass_)) {
      fail("cannot initialise Dear ImGui");
      return false;
    }
    imgui_ready_ = true;
    auto uploaded =
        vk_->submit_and_wait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
    return bool(uploaded);
  }

  // Left button: look around; WASD/QE: move (shift: faster); right button: move the light. Returns
  // whether the camera or the light moved.
  // How responsive the window was, moving and still apart: the targets are what the pacer aims at.
  void report_frames(uint32_t frames, std::vector<float> moving_ms, std::vector<float> still_ms,
                     uint32_t moving_divisor) const {
    auto times = [](std::vector<float>& ms) {
      std::sort(ms.begin(), ms.end());
      char text[128];
      std::snprintf(text, sizeof text, "frame time median %.0f ms, 90th percentile %.0f ms, max %.0f ms",
                    double(ms[ms.size() / 2]), double(ms[ms.size() * 9 / 10]), double(ms.back()));
      return std::string(text);
    };
    const uint32_t w = swapchain_.extent.width, h = swapchain_.extent.height;
    std::printf("path_tracer: %u frames at %ux%u\n", frames, w, h);
    if (!moving_ms.empty())
      std::printf("  moving: %zu frames, traced at %ux%u (1/%u), %s (target %.0f ms)\n", moving_ms.size(),
                  (w + moving_divisor - 1) / moving_divisor, (h + moving_divisor - 1) / moving_divisor,
                  moving_divisor, times(moving_ms).c_str(), adaptive_ ? double(moving_target_ms_) : 0.0);
    if (!still_ms.empty())
      std::printf(
          "  still: %zu frames, traced at %ux%u, %s (target %.0f ms); %u samples per pixel at the end\n",
          still_ms.size(), w, h, times(still_ms).c_str(), adaptive_ ? double(target_ms_) : 0.0,
          renderer_->samples_done());
  }

  // --move-frames: the camera turns a little each frame, as a user dragging the mouse would.
  // A scene edited in the panel or by the mouse; an unpack that fails keeps the previous scene.
  void change_scene(const Scene& scene) {
    if (auto ok = renderer_->set_scene(scene); !ok)
      std::fprintf(stderr, "path_tracer: %s\n", printable(ok.error().message).c_str());
  }

  bool turn_camera() {
    Camera camera = renderer_->camera();
    camera.yaw_degrees += 0.5f;
    renderer_->set_camera(camera);
    return true;
  }

  bool handle_input(float dt) {
    if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse) {
      glfwGetCursorPos(window_, &mouse_x_, &mouse_y_);
      return false;
    }
    double x = 0, y = 0;
    glfwGetCursorPos(window_, &x, &y);
    const float dx = float(x - mouse_x_), dy = float(y - mouse_y_);
    mouse_x_ = x, mouse_y_ = y;
    Camera camera = renderer_->camera();
    bool camera_changed = false;
    if (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS && (dx != 0 || dy != 0)) {
      camera.yaw_degrees += dx * 0.1f;
      camera.pitch_degrees = std::clamp(camera.pitch_degrees - dy * 0.1f, -89.0f, 89.0f);
      camera_changed = true;
    }
    const float speed = (glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ? 25.0f : 5.0f) * dt;
    const float yaw = camera.yaw_degrees * 3.14159265f / 180.0f;
    const float forward[3] = {std::sin(yaw), 0, std::cos(yaw)}, right[3] = {std::cos(yaw), 0, -std::sin(yaw)};
    auto move = [&](int key, const float* axis, float sign) {
      if (glfwGetKey(window_, key) != GLFW_PRESS) return;
      for (int i = 0; i < 3; ++i) camera.position[i] += axis[i] * sign * speed;
      camera_changed = true;
    };
    const float up[3] = {0, 1, 0};
    move(GLFW_KEY_W, forward, 1), move(GLFW_KEY_S, forward, -1), move(GLFW_KEY_D, right, 1);
    move(GLFW_KEY_A, right, -1), move(GLFW_KEY_E, up, 1), move(GLFW_KEY_Q, up, -1);
    if (camera_changed) renderer_->set_camera(camera);
    if (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS && (dx != 0 || dy != 0)) {
      Scene scene = renderer_->scene();
      scene.light.center[0] += dx * 0.01f;
      scene.light.center[2] -= dy * 0.01f;
      clamp_light(scene.light);
      change_scene(scene);
      return true;
    }
    return camera_changed;
  }

  // The light stays inside the room, as in the tutorial.
  static void clamp_light(Light& light) {
    for (int axis : {0, 2}) {
      const float limit = 4.5f - light.half_size[axis];
      light.center[axis] = std::clamp(light.center[axis], -limit, limit);
    }
  }

  // A light without area, collapsed by default: its intensity, position or direction and cone. Every
  // value stays one the scene file could hold (load_scene's rules).
  static bool light_panel(size_t index, SceneLight& light) {
    const std::string title = (light.name.empty() ? "Light " + std::to_string(index) : light.name) +
                              "##light" + std::to_string(index);
    if (!ImGui::CollapsingHeader(title.c_str())) return false;
    ImGui::PushID(int(index));
    bool changed = ImGui::SliderFloat("Intensity", &light.intensity, 0.01f, 50.0f);
    if (light.type != SceneLight::Type::directional)
      changed |= ImGui::SliderFloat3("Position", light.position.data(), -10.0f, 10.0f);
    if (light.type != SceneLight::Type::point) {
      Vec3 direction = light.direction;
      if (ImGui::SliderFloat3("Direction", direction.data(), -1.0f, 1.0f)) {
        const float length = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] +
                                       direction[2] * direction[2]);
        if (length > 1e-3f) {  // a zero direction is no light: keep the last one
          for (float& c : direction) c /= length;
          light.direction = direction, changed = true;
        }
      }
    }
    if (light.type == SceneLight::Type::spot) {
      changed |= ImGui::SliderFloat("Umbra (degrees)", &light.umbra_degrees, 1.0f, 180.0f);
      changed |= ImGui::SliderFloat("Penumbra (degrees)", &light.penumbra_degrees, 0.0f, 179.0f);
      light.penumbra_degrees =
          std::min(light.penumbra_degrees, light.umbra_degrees - 0.5f);  // umbra > penumbra
      light.penumbra_degrees = std::max(light.penumbra_degrees, 0.0f);
    }
    light.intensity = std::max(light.intensity, 0.01f);
    ImGui::PopID();
    return changed;
  }

  void panel(float dt) {
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::Begin("Settings", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    RenderSettings s = renderer_->settings();
    int bounces = int(s.bounces), spf = int(s.samples_per_frame);
    ImGui::SliderInt("Bounces", &bounces, 1, 8);
    if (!adaptive_) ImGui::SliderInt("Samples per frame", &spf, 1, 32);
    int estimator = int(s.estimator);
    const char* titles[std::size(kEstimatorNames)];
    for (size_t i = 0; i < std::size(titles); ++i) titles[i] = kEstimatorNames[i].title;
    ImGui::Combo("Estimator", &estimator, titles, int(std::size(titles)));
    s.estimator = Estimator(estimator);
    s.next_event_estimation = s.estimator != Estimator::bsdf;
    // Collapsed by default, so the panel keeps clear of the walls (the window test looks at them).
    if (ImGui::CollapsingHeader("Sampling and pacing")) {
      ImGui::Checkbox("Adapt samples per frame", &adaptive_);
      if (adaptive_) {
        ImGui::SliderFloat("Frame target (ms)", &target_ms_, 20.0f, 1000.0f);
        ImGui::SliderFloat("Moving frame target (ms)", &moving_target_ms_, 10.0f, 200.0f);
      }
      bool sobol = s.sampler == Sampler::sobol;
      ImGui::Checkbox("Sobol sampler", &sobol);
      s.sampler = sobol ? Sampler::sobol : Sampler::random;
      bool solid_angle = s.light_sampling == LightSampling::solid_angle;
      ImGui::Checkbox("Solid-angle light sampling", &solid_angle);
      s.light_sampling = solid_angle ? LightSampling::solid_angle : LightSampling::area;
      bool one = s.delta_lights == DeltaLights::one;
      ImGui::Checkbox("One delta light per vertex", &one);
      s.delta_lights = one ? DeltaLights::one : DeltaLights::all;
      int roulette = int(s.roulette_start);
      ImGui::SliderInt("Roulette from bounce", &roulette, 0, 8);
      s.roulette_start = uint32_t(roulette);
    }
    ImGui::Checkbox("Show only last bounce", &s.last_bounce_only);
    ImGui::SliderFloat("Exposure", &s.exposure, 0.1f, 8.0f);
    s.bounces = uint32_t(bounces), s.samples_per_frame = uint32_t(spf);
    renderer_->set_settings(s);
    Scene scene = renderer_->scene();
    bool light_changed = false;
    if (scene.area_light) {
      light_changed |= ImGui::SliderFloat("Light intensity", &scene.light.intensity, 1.0f, 50.0f);
      light_changed |= ImGui::SliderFloat("Light width", &scene.light.half_size[0], 0.5f, 3.0f);
      light_changed |= ImGui::SliderFloat("Light height", &scene.light.half_size[2], 0.5f, 3.0f);
      light_changed |= ImGui::ColorEdit3("Light color", scene.light.color.data());
    }
    for (size_t i = 0; i < scene.lights.size(); ++i) light_changed |= light_panel(i, scene.lights[i]);
    if (light_changed) {
      clamp_light(scene.light);
      change_scene(scene);
    }
    ImGui::Text("%u spp, %.1f ms/frame, %u/frame, traced at 1/%u", renderer_->samples_done(), dt * 1000.0f,
                renderer_->settings().samples_per_frame, renderer_->render_divisor());
    ImGui::TextUnformatted("LMB + WASDQE: camera, RMB: light");
    ImGui::End();
  }

  // Samples per frame from the last frame's GPU time (its fence has been waited for, so its timestamps
  // are ready), toward the target; while the camera or the light moves, 1 sample, traced at the fraction
  // of the size that meets the moving target (back to the full size, and accumulating, when still).
  void pace() {
    if (last_batch_ > 0) pacer_.measured(renderer_->last_trace_ms(), last_batch_, last_pixels_);
    RenderSettings s = renderer_->settings();
    if (adaptive_) {
      pacer_.set_target_ms(target_ms_);
      pacer_.set_moving_target_ms(moving_target_ms_);
      const uint64_t pixels = uint64_t(renderer_->width()) * renderer_->height();  // the full size
      s.samples_per_frame = pacer_.samples_for_next_frame(moving_, pixels);        // (1 while moving)
      renderer_->set_settings(s);
      renderer_->set_render_divisor(pacer_.divisor_for_next_frame(moving_, pixels));
    } else {
      renderer_->set_render_divisor(1);
    }
    last_batch_ = s.samples_per_frame;
    last_pixels_ = uint64_t(renderer_->render_width()) * renderer_->render_height();
  }

  bool draw_frame(float dt, bool capture) {
    vkWaitForFences(vk_->device, 1, &in_flight_, VK_TRUE, UINT64_MAX);
    uint32_t index = 0;
    VkResult acquired =
        vkAcquireNextImageKHR(vk_->device, swapchain_.handle, UINT64_MAX, acquired_, VK_NULL_HANDLE, &index);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) return recreate_swapchain();
    if (acquired != VK_SUCCESS && acquired != VK_SUBOPTIMAL_KHR)
      return fail("cannot acquire a swapchain image") == 0;
    vkResetFences(vk_->device, 1, &in_flight_);

    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    panel(dt);
    ImGui::Render();
    pace();

    vkResetCommandBuffer(cmd_, 0);
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    vkBeginCommandBuffer(cmd_, &begin);
    renderer_->record(cmd_, swapchain_.images[index], swapchain_.views[index],
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    VkRenderPassBeginInfo pass{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    pass.renderPass = overlay_pass_;
    pass.framebuffer = swapchain_.framebuffers[index];
    pass.renderArea = {{0, 0}, swapchain_.extent};
    vkCmdBeginRenderPass(cmd_, &pass, VK_SUBPASS_CONTENTS_INLINE);
    ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd_);
    vkCmdEndRenderPass(cmd_);
    std::unique_ptr<bootstrap::HostBuffer> readback;
    if (capture && can_capture_) readback = record_capture(swapchain_.images[index]);
    vkEndCommandBuffer(cmd_);

    VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.waitSemaphoreCount = 1;
    submit.pWaitSemaphores = &acquired_;
    submit.pWaitDstStageMask = &wait_stage;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd_;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &rendered_;
    if (vkQueueSubmit(vk_->queue, 1, &submit, in_flight_) != VK_SUCCESS)
      return fail("queue submit failed") == 0;
    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &rendered_;
    present.swapchainCount = 1;
    present.pSwapchains = &swapchain_.handle;
    present.pImageIndices = &index;
    VkResult presented = vkQueuePresentKHR(vk_->queue, &present);
    if (readback) {
      vkWaitForFences(vk_->device, 1, &in_flight_, VK_TRUE, UINT64_MAX);
      screenshot_.assign(static_cast<const uint8_t*>(readback->mapped),
                         static_cast<const uint8_t*>(readback->mapped) + readback->size);
    }
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR ||
        uint32_t(w) != swapchain_.extent.width || uint32_t(h) != swapchain_.extent.height) {
      vkWaitForFences(vk_->device, 1, &in_flight_, VK_TRUE, UINT64_MAX);
      return recreate_swapchain();
    }
    return true;
  }

  // Copies the presented image (what the window shows, panel included) to a host buffer.
  std::unique_ptr<bootstrap::HostBuffer> record_capture(VkImage image) {
    const VkExtent2D e = swapchain_.extent;
    auto buffer = bootstrap::create_host_buffer(*vk_, VkDeviceSize(e.width) * e.height * 4,
                                                VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    if (!buffer) return nullptr;
    auto barrier = [&](VkImageLayout from, VkImageLayout to, VkAccessFlags src, VkAccessFlags dst) {
      bootstrap::image_barrier(cmd_, image, from, to, src, dst,
                               VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                               VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    };
    barrier(VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
            VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {e.width, e.height, 1};
    vkCmdCopyImageToBuffer(cmd_, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, (*buffer)->buffer, 1, &copy);
    barrier(VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
            VK_ACCESS_TRANSFER_READ_BIT, 0);
    return std::move(buffer.value());
  }

  // The captured bytes (the swapchain's 8-bit format, sRGB-encoded already) as a PNG.
  std::string write_rgba8(const std::string& path, const std::vector<uint8_t>& bytes, uint32_t w, uint32_t h,
                          const std::vector<std::filesystem::path>& inputs) {
    const bool bgra =
        swapchain_.format == VK_FORMAT_B8G8R8A8_SRGB || swapchain_.format == VK_FORMAT_B8G8R8A8_UNORM;
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    for (size_t i = 0; i < size_t(w) * h; ++i)
      for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = bytes[i * 4 + (bgra ? 2 - c : c)];
    return write_png_rgb8(path, rgb, w, h, inputs);
  }

  void destroy() {
    if (!vk_) {
      if (window_) glfwDestroyWindow(window_), window_ = nullptr;
      return;
    }
    vkDeviceWaitIdle(vk_->device);
    if (imgui_ready_) {
      ImGui_ImplVulkan_Shutdown();
      ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext();
      imgui_ready_ = false;
    }
    renderer_.reset();
    dearchiver_.reset();
    if (imgui_pool_) vkDestroyDescriptorPool(vk_->device, imgui_pool_, nullptr);
    if (acquired_) vkDestroySemaphore(vk_->device, acquired_, nullptr);
    if (rendered_) vkDestroySemaphore(vk_->device, rendered_, nullptr);
    if (in_flight_) vkDestroyFence(vk_->device, in_flight_, nullptr);
    destroy_swapchain_views();
    if (overlay_pass_) vkDestroyRenderPass(vk_->device, overlay_pass_, nullptr);
    if (swapchain_.handle) vkDestroySwapchainKHR(vk_->device, swapchain_.handle, nullptr);
    imgui_pool_ = VK_NULL_HANDLE, acquired_ = rendered_ = VK_NULL_HANDLE, in_flight_ = VK_NULL_HANDLE;
    overlay_pass_ = VK_NULL_HANDLE, swapchain_.handle = VK_NULL_HANDLE;
    vk_->destroy_device();
    validation_failures_ = report_validation(*vk_);
    if (surface_) vkDestroySurfaceKHR(vk_->instance, surface_, nullptr);
    surface_ = VK_NULL_HANDLE;
    vk_.reset();
    if (window_) glfwDestroyWindow(window_), window_ = nullptr;
    glfwTerminate();
  }

  GLFWwindow* window_ = nullptr;
  std::unique_ptr<bootstrap::VulkanContext> vk_;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  Swapchain swapchain_;
  VkRenderPass overlay_pass_ = VK_NULL_HANDLE;
  std::unique_ptr<Dearchiver> dearchiver_;
  std::unique_ptr<Renderer> renderer_;
  VkSemaphore acquired_ = VK_NULL_HANDLE, rendered_ = VK_NULL_HANDLE;
  VkFence in_flight_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkDescriptorPool imgui_pool_ = VK_NULL_HANDLE;
  bool imgui_ready_ = false;
  double mouse_x_ = 0, mouse_y_ = 0;
  size_t validation_failures_ = 0;
  bool can_capture_ = false;
  std::vector<uint8_t> screenshot_;
  // Frame pacing: samples per frame follow the measured cost toward a frame-time target, 1 while moving.
  bool adaptive_ = true;
  float target_ms_ = 100.0f;
  float moving_target_ms_ = 50.0f;  // a whole frame while the view moves
  FramePacer pacer_;
  bool moving_ = false;       // the camera or the light moved this frame
  uint32_t last_batch_ = 0;   // samples per pixel of the last recorded frame (0: none yet)
  uint64_t last_pixels_ = 0;  // pixels it traced
};

}  // namespace

int run_windowed(const Options& options) {
  Window window;
  return window.run(options);
}

}  // namespace statepack::path_tracer
