// DXC's [[vk::combinedImageSampler]]: a Texture and a SamplerState declared with it at the same set and
// binding are one VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER descriptor (Vulkan lets a separate image
// variable and a sampler variable both read a combined descriptor). glslang parses the attribute and
// ignores it, warning "'combinedImageSampler' : unrecognized attribute" at the attribute's line; the
// layout (pipeline_layout.cpp) pairs the variables found here instead of moving one to a binding of
// its own.
#pragma once

#include <functional>
#include <string>
#include <vector>

#define ENABLE_HLSL 1
#include <glslang/Public/ShaderLang.h>

namespace statepack::packager {

struct AttributeSite {
  std::string file;  // as glslang names it in its log
  int line = 0;
};

// The textures and samplers the attribute was written on: for each site, the first global texture or
// sampler named after the attribute in that file's text (the attribute precedes its declaration;
// glslang keeps no line for those globals). `text_of` gives a file's text by glslang's name for it.
std::vector<std::string> combined_image_sampler_variables(
    const glslang::TShader& shader, const std::vector<AttributeSite>& sites,
    const std::function<const std::string*(const std::string& file)>& text_of);

}  // namespace statepack::packager
