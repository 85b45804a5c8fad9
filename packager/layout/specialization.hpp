// A pipeline's specialization constants, resolved by name against what its shaders declare: each
// name finds its SpecId in every stage it is given for, and each value is converted to the declared type
// (bool, int, uint, float, double and 64-bit integers), or it is an error at the notation element.
#pragma once

#include <vector>

#include "format/archive_format.hpp"
#include "notation/diagnostics.hpp"
#include "notation/notation.hpp"
#include "pipeline_layout.hpp"

namespace statepack::packager {

// Appends one format::SpecConstant per (constant, stage) to `out`; false after reporting an error.
bool resolve_constants(const PipelineDesc& pipeline, const std::vector<StageInput>& stages,
                       std::vector<format::SpecConstant>& out, Diagnostics& diagnostics);

}  // namespace statepack::packager
