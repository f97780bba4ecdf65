#pragma once
// Private to the mesh loaders: their errors, which always name the asset first (one_line.hpp
// flattens the libraries' multi-line messages). Messages may quote the asset's bytes (the JSON
// parser's "last read"): bytes that are not UTF-8 are escaped, for the service's JSON answers.
#include <cstddef>
#include <string>

#include "oer/core/error.hpp"
#include "oer/core/one_line.hpp"

namespace oer::mesh_detail {

[[noreturn]] inline void fail(ErrorKind kind, const std::string& asset, const std::string& what) {
    throw Error(kind, detail::valid_utf8(asset + ": " + what));
}

using detail::one_line;

}  // namespace oer::mesh_detail
