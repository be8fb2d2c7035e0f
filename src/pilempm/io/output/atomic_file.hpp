#pragma once
// Writing output files so that an error never leaves a half-written file and never destroys a
// good older one: the content goes to FILE.tmp in the same folder, is synced, then renamed over
// FILE. Every file the program writes goes through here.
#include <filesystem>
#include <string_view>

namespace pilempm {

/// Writes `content` to FILE.tmp next to `path`, then renames it over `path`. Throws Error (and
/// removes the .tmp) when anything fails; `path` is then untouched.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

/// Creates the folder if needed and checks that a file can be created in it (throws Error).
void prepare_output_directory(const std::filesystem::path& directory);
/// Checks that the folder of an output file exists and is writable (throws Error).
void check_output_file(const std::filesystem::path& file);

}  // namespace pilempm
