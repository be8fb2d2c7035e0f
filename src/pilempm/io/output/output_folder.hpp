#pragma once
// The output folder of a run (docs/reliability.md, "Output folders"). A run takes its folder with
// claim_output_folder: a folder that holds another run's files is refused unless the caller asks
// to overwrite it (then exactly that run's files are removed first, never a file pilempm did not
// write) or the run continues its own earlier part there (a restart, a study's --resume).
// From then on every file written into the folder or below it (write_file_atomically, the
// checkpoints, the figures) is listed in DIR/.pilempm-files, which tells a later run what is
// pilempm's. Temporary files (FILE.<process>-<count>.tmp) left by a run that was killed are
// removed when the next run takes the folder; those of this process by
// remove_own_temporary_files when a command ends, with an error too.
#include <filesystem>
#include <string>
#include <vector>

namespace pilempm {

/// The list of the files a run wrote into its folder, one path a line, relative to the folder.
inline constexpr const char* kOutputListName = ".pilempm-files";

struct OutputFolderOptions {
  bool overwrite = false;  ///< remove the files of the run that is there first
  bool resume = false;     ///< the folder holds this run's own earlier part: keep it
};

struct OutputFolderClaim {
  std::vector<std::filesystem::path> removed_temporary;  ///< stray temporary files removed
  std::vector<std::filesystem::path> removed_files;      ///< the earlier run's (overwrite)
};

/// Takes `directory` for a run: creates it if needed and checks that it is writable; removes
/// the temporary files of processes that no longer run; refuses (throws Error naming the folder
/// and some of the files) a folder holding another run's files unless `overwrite` (which
/// removes them first: the files of its list, those of the lists in its subfolders, and the
/// files only pilempm writes, listed in docs/reliability.md) or `resume`. Then lists every file
/// written below it in its kOutputListName.
OutputFolderClaim claim_output_folder(const std::filesystem::path& directory,
                                      const OutputFolderOptions& options = {});

/// The files of another run in `directory` (empty: none), as claim_output_folder sees them.
std::vector<std::filesystem::path> earlier_run_files(const std::filesystem::path& directory);

/// Lists `file` in the list of the claimed folder it lies in, if any (called for every file
/// written, by temporary_path_for). Throws Error when the list cannot be written.
void note_output_file(const std::filesystem::path& file);

/// Removes the temporary files of this process left in the claimed folders (a write that an
/// error or an exception cut short); returns them.
std::vector<std::filesystem::path> remove_own_temporary_files();

}  // namespace pilempm
