#pragma once
// Private to image_io*.cpp: the errors of image reading and writing, which always name the
// file (or the in-memory name) first. Messages may quote the file's bytes (a header's names):
// bytes that are not UTF-8 are escaped (one_line.hpp), for the service's JSON answers.
#include <string>

#include "oer/core/error.hpp"
#include "oer/core/one_line.hpp"

namespace oer::image_io_detail {

[[noreturn]] inline void fail(ErrorKind kind, const std::string& name, const std::string& what) {
    throw Error(kind, detail::valid_utf8(name + ": " + what));
}

using detail::one_line;

}  // namespace oer::image_io_detail
