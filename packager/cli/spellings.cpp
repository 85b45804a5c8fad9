#include "spellings.hpp"

namespace statepack::packager {

std::string notation_name(EnumTable table, uint32_t value, const std::string& vulkan) {
  for (const auto& [name, v] : table)
    if (v == value && v != kUnsupportedValue) return std::string(name);
  return vulkan;
}

}  // namespace statepack::packager
