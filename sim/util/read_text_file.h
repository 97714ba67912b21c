// A whole file as text. The callers give their own error messages: a missing file is found
// before (std::filesystem), a read failure is returned as nullopt.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

namespace rtusim {

// The bytes of `path`, or nullopt when it cannot be opened or read.
std::optional<std::string> read_text_file(const std::filesystem::path& path);

}  // namespace rtusim
