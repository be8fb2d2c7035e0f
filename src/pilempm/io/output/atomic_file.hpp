#pragma once
// Writing output files so that an error never leaves a half-written file and never destroys a
// good older one: the content goes to FILE.<process>-<count>.tmp in the same folder (a name no
// other write uses), is synced, then renamed over FILE. Every file the program writes goes through
// here.
#include <filesystem>
#include <string_view>

namespace pilempm {

/// Writes `content` to a new temporary file next to `path` (temporary_path_for), then renames it
/// over `path`. Throws Error (and removes the temporary file) when anything fails, a full disk
/// included; `path` is then untouched.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);
/// A name for a temporary file next to `path` that no other write uses, not even one of another
/// process or thread into the same folder: FILE.<process>-<count>.tmp. Lists `path` among the
/// files of the run folder it lies in, if one was claimed (output_folder.hpp).
std::filesystem::path temporary_path_for(const std::filesystem::path& path);

/// Creates the folder if needed and checks that a file can be created in it (throws Error).
void prepare_output_directory(const std::filesystem::path& directory);
/// Checks that the folder of an output file exists and is writable (throws Error).
void check_output_file(const std::filesystem::path& file);

}  // namespace pilempm
