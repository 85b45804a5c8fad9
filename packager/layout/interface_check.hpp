// Checks between a graphics pipeline's notation and its compiled shaders: what one stage writes the
// next must read with the same type, every vertex-shader input must come from the input layout with a
// compatible format, and every fragment output must land on a render target of its kind. Vulkan
// reports these only at pipeline creation, at draw time, or never (a blank picture); here each is an
// error at the notation element involved, naming both sides.
#pragma once

#include <optional>
#include <unordered_map>
#include <vector>

#include "format/archive_format.hpp"
#include "format/spirv_walk.hpp"
#include "notation/diagnostics.hpp"
#include "notation/notation.hpp"
#include "pipeline_layout.hpp"

namespace statepack::packager {

// `g` is the pipeline's state with its render pass applied (formats of the subpass). Returns false
// when an error was reported; warnings (unused input-layout elements, formats some devices do not
// support for their use) do not fail.
// "vertex shader 'Name'": a shader as messages name it, by Diligent's stage words (the notation's slots).
std::string stage_text(const ShaderDesc& shader);

bool check_graphics_interfaces(const PipelineDesc& p, const format::GraphicsState& g,
                               const std::vector<StageInput>& stages, const SourceTexts& sources,
                               Diagnostics& diag);

// Walked modules by their SPIR-V, so that pipelines sharing a shader walk it once.
using WalkedModules = std::unordered_map<const std::vector<uint32_t>*, std::optional<spirv::Module>>;

// Warns when a compute pipeline's work-group size (with the pipeline's specialization constants) is
// beyond what Vulkan guarantees every device (maxComputeWorkGroupSize 128 x 128 x 64, 128 invocations):
// devices with lower limits refuse it, and the dearchiver checks the device's own limits at unpack.
void warn_compute_work_group(const PipelineDesc& p, const StageInput& stage,
                             const std::vector<format::SpecConstant>& constants, WalkedModules& walked,
                             Diagnostics& diag);

// Warns about color attachments of a render pass whose format Vulkan does not require devices to support
// as a color attachment (once per attachment, at its pAttachments entry).
void warn_render_pass_formats(const RenderPassDesc& pass, const SourceTexts& sources, Diagnostics& diag);

}  // namespace statepack::packager
