// The path tracer's two ways to run, sharing options and set-up.
#pragma once

#include <memory>
#include <string>

#include "renderer.hpp"
#include "statepack/bootstrap/host_tools.hpp"

namespace statepack::path_tracer {

// Messages and paths carry names from the scene file, the archive and the command line: every one the
// sample prints goes through this, so no byte of them can drive the terminal.
using bootstrap::printable;

struct Options {
  bool headless = false;
  std::string archive = STATEPACK_PATH_TRACER_ARCHIVE;
  std::string scene = STATEPACK_DEFAULT_SCENE;
  uint32_t width = 640, height = 480, spp = 256, frames = 0;
  uint32_t move_frames = 0;  // windowed: the camera turns by itself for these first frames (a moving view)
  RenderSettings settings;
  std::string out = "path_tracer.png";
  std::string screenshot;
  bool validation = true;
  bool watch = false;  // reload the archive when a new build of it is written
};

int run_headless(const Options& options);
int run_windowed(const Options& options);

// Loads the archive into a dearchiver for `vk`; prints the reason and returns null on failure.
std::unique_ptr<Dearchiver> load_archive(bootstrap::VulkanContext& vk, const std::string& path);
// Prints validation messages; returns how many there were.
size_t report_validation(const bootstrap::VulkanContext& vk);

}  // namespace statepack::path_tracer
