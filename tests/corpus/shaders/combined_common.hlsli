// Declared in an include: the attribute is found in this file's text too.
[[vk::combinedImageSampler]] [[vk::binding(2, 0)]] Texture2D detail;
[[vk::combinedImageSampler]] [[vk::binding(2, 0)]] SamplerState detailSampler;
