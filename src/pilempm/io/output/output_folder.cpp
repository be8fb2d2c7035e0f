// The output folder of a run: see output_folder.hpp.
#include "pilempm/io/output/output_folder.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <string_view>

#include "pilempm/core/error.hpp"
#include "pilempm/io/output/atomic_file.hpp"

namespace pilempm {

namespace fs = std::filesystem;

namespace {

// How deep below a run's folder its own subfolders go (a study's DIR/case/mpm/).
constexpr int kMaxDepth = 4;

bool all_digits(std::string_view text) {
  return !text.empty() &&
         std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool ends_with(std::string_view text, std::string_view tail) {
  return text.size() >= tail.size() && text.substr(text.size() - tail.size()) == tail;
}

// The names only pilempm writes (docs/reliability.md): a folder without a list that holds one of
// these holds a run of a pilempm without the list; they are that run's files.
bool pilempm_file_name(std::string_view name) {
  static constexpr std::string_view kNames[] = {
      "particles.pvd", "energies.csv",    "bodies.csv",         "pile.csv",
      "mpm_case.toml", "summary.json",    "summary.md",         "summary.csv",
      "figures.json",  "plot_figures.py", "plot_calibration.py"};
  if (std::find(std::begin(kNames), std::end(kNames), name) != std::end(kNames)) return true;
  if (name.starts_with("particles_") && ends_with(name, ".vtu"))
    return all_digits(name.substr(10, name.size() - 14));
  if (name.starts_with("bodies_") && ends_with(name, ".vtu"))
    return all_digits(name.substr(7, name.size() - 11));
  if (name.starts_with("checkpoint_") && ends_with(name, ".h5")) {
    const std::string_view rest = name.substr(11);
    return all_digits(rest.substr(0, rest.find('_')));
  }
  return name.starts_with("fields_") &&
         (ends_with(name, ".csv") || ends_with(name, ".vtu") || ends_with(name, ".png"));
}

// The process of a temporary file FILE.<process>-<count>.tmp, or 0 when `name` is not one.
long temporary_file_process(std::string_view name) {
  if (!ends_with(name, ".tmp")) return 0;
  const std::string_view stem = name.substr(0, name.size() - 4);
  const std::size_t dot = stem.rfind('.');
  if (dot == std::string_view::npos || dot == 0) return 0;
  const std::string_view tag = stem.substr(dot + 1);
  const std::size_t dash = tag.find('-');
  if (dash == std::string_view::npos || !all_digits(tag.substr(0, dash)) ||
      !all_digits(tag.substr(dash + 1)) || dash > 9)
    return 0;
  return std::stol(std::string(tag.substr(0, dash)));
}

bool process_runs(long pid) {
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

bool is_folder(const fs::path& path) {
  std::error_code ec;
  return fs::is_directory(fs::symlink_status(path, ec));
}

bool is_plain_file(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(path, ec);
  return !ec && (fs::is_regular_file(status) || fs::is_symlink(status));
}

// The paths of a folder's list that lie inside it (a list that was edited cannot point outside).
std::vector<fs::path> listed_files(const fs::path& directory) {
  std::vector<fs::path> files;
  std::ifstream in(directory / kOutputListName);
  std::string line;
  while (std::getline(in, line)) {
    const fs::path relative = fs::path(line).lexically_normal();
    if (line.empty() || relative.is_absolute() || relative.empty() ||
        *relative.begin() == fs::path(".."))
      continue;
    files.push_back(directory / relative);
  }
  return files;
}

// A subfolder that belongs to a run: a run's own MPM output (mpm/) or a folder with a list.
bool run_subfolder(const fs::path& path) {
  return is_folder(path) && (path.filename() == "mpm" || is_plain_file(path / kOutputListName));
}

void collect_run_files(const fs::path& directory, int depth, std::set<fs::path>& files,
                       std::vector<fs::path>& folders) {
  for (const fs::path& listed : listed_files(directory))
    if (is_plain_file(listed)) files.insert(listed);
  std::error_code ec;
  for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path path = it->path();
    const std::string name = path.filename().string();
    if (is_plain_file(path) && pilempm_file_name(name)) files.insert(path);
    if (depth < kMaxDepth && run_subfolder(path)) {
      folders.push_back(path);
      collect_run_files(path, depth + 1, files, folders);
    }
  }
}

// Temporary files of pilempm in `directory` and its run subfolders: those of processes that no
// longer run (`own` false), or those of this process (`own` true).
void collect_temporary_files(const fs::path& directory, int depth, bool own,
                             std::vector<fs::path>& files) {
  std::error_code ec;
  for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path path = it->path();
    const std::string name = path.filename().string();
    if (is_plain_file(path)) {
      const long pid = temporary_file_process(name);
      const bool stray =
          own ? pid == ::getpid()
              : (pid > 0 && pid != ::getpid() && !process_runs(pid)) ||
                    // the fixed name of older versions: FILE.tmp of a run file
                    (ends_with(name, ".tmp") && pilempm_file_name(name.substr(0, name.size() - 4)));
      if (stray) files.push_back(path);
    } else if (depth < kMaxDepth && (own ? is_folder(path) : run_subfolder(path))) {
      collect_temporary_files(path, depth + 1, own, files);
    }
  }
}

std::vector<fs::path> remove_files(const std::vector<fs::path>& files) {
  std::vector<fs::path> removed;
  for (const fs::path& file : files) {
    std::error_code ec;
    if (fs::remove(file, ec)) removed.push_back(file);
  }
  return removed;
}

// The folders whose files go into a list: the claimed folders, with what each list holds.
struct Claim {
  fs::path directory;  // absolute, normal form
  std::set<std::string> listed;
};

std::mutex& claims_mutex() {
  static std::mutex mutex;
  return mutex;
}

std::vector<Claim>& claims() {
  static std::vector<Claim> list;
  return list;
}

fs::path absolute_path(const fs::path& path) {
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  return (ec ? path : absolute).lexically_normal();
}

// `path` lies in `directory` (both absolute and normal): the relative path, else empty.
fs::path inside(const fs::path& path, const fs::path& directory) {
  auto d = directory.begin();
  auto p = path.begin();
  for (; d != directory.end(); ++d, ++p) {
    if (d->empty()) continue;  // the trailing separator of "dir/"
    if (p == path.end() || *p != *d) return {};
  }
  fs::path relative;
  for (; p != path.end(); ++p) relative /= *p;
  return relative;
}

void append_to_list(const fs::path& directory, const std::string& line) {
  const fs::path list = directory / kOutputListName;
  const int fd = ::open(list.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  bool ok = fd >= 0;
  if (ok) {
    const std::string text = line + "\n";
    ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
    const int saved = errno;
    ok = (::close(fd) == 0) && ok;
    if (!ok && errno == 0) errno = saved;
  }
  if (!ok)
    throw Error(fmt::format("cannot write the list of the run's files {}: {}", list.string(),
                            std::strerror(errno)));
}

std::string listed_names(const std::vector<fs::path>& files, const fs::path& directory) {
  std::string names;
  for (std::size_t k = 0; k < files.size() && k < 4; ++k)
    names += (k == 0 ? "" : ", ") + files[k].lexically_relative(directory).generic_string();
  if (files.size() > 4) names += ", ...";
  return names;
}

}  // namespace

std::vector<fs::path> earlier_run_files(const fs::path& directory) {
  std::set<fs::path> files;
  std::vector<fs::path> folders;
  if (is_folder(directory)) collect_run_files(directory, 0, files, folders);
  return {files.begin(), files.end()};
}

OutputFolderClaim claim_output_folder(const fs::path& directory,
                                      const OutputFolderOptions& options) {
  const fs::path dir = directory.empty() ? fs::path(".") : directory;
  prepare_output_directory(dir);
  OutputFolderClaim claim;
  std::vector<fs::path> stray;
  collect_temporary_files(dir, 0, false, stray);
  claim.removed_temporary = remove_files(stray);

  std::set<fs::path> files;
  std::vector<fs::path> folders;
  collect_run_files(dir, 0, files, folders);
  if (!files.empty() && !options.resume) {
    const std::vector<fs::path> earlier(files.begin(), files.end());
    if (!options.overwrite)
      throw Error(fmt::format(
          "output folder {} holds the files of another run ({} file{}: {}): give another "
          "output folder, or --overwrite to remove that run's files first (only the files "
          "pilempm wrote there, docs/reliability.md)",
          dir.string(), earlier.size(), earlier.size() == 1 ? "" : "s",
          listed_names(earlier, dir)));
    claim.removed_files = remove_files(earlier);
    // The folders of the earlier run that are empty now (a study's tests/, a run's mpm/).
    const fs::path top = absolute_path(dir);
    for (const fs::path& file : claim.removed_files) {
      std::error_code ec;
      for (fs::path parent = absolute_path(file).parent_path();
           parent != top && !inside(parent, top).empty() && fs::remove(parent, ec);
           parent = parent.parent_path()) {
      }
    }
    if (claim.removed_files.size() != earlier.size())
      throw Error(
          fmt::format("output folder {}: cannot remove the files of the earlier run "
                      "({} of {} removed)",
                      dir.string(), claim.removed_files.size(), earlier.size()));
  }
  if (!options.resume) {
    // The lists of the earlier run, and the run subfolders it leaves empty (deepest first).
    std::error_code ec;
    for (auto it = folders.rbegin(); it != folders.rend(); ++it) {
      fs::remove(*it / kOutputListName, ec);
      fs::remove(*it, ec);  // only when empty
    }
    fs::remove(dir / kOutputListName, ec);
  }

  Claim entry{absolute_path(dir), {}};
  for (const fs::path& listed : listed_files(dir))
    entry.listed.insert(listed.lexically_relative(dir).generic_string());
  const std::lock_guard lock(claims_mutex());
  std::vector<Claim>& all = claims();
  all.erase(std::remove_if(all.begin(), all.end(),
                           [&entry](const Claim& c) { return c.directory == entry.directory; }),
            all.end());
  all.push_back(std::move(entry));
  return claim;
}

void note_output_file(const fs::path& file) {
  const std::lock_guard lock(claims_mutex());
  std::vector<Claim>& all = claims();
  if (all.empty()) return;
  const fs::path path = absolute_path(file);
  Claim* owner = nullptr;
  fs::path relative;
  for (Claim& c : all) {  // the innermost claimed folder the file lies in
    const fs::path r = inside(path, c.directory);
    if (r.empty()) continue;
    if (owner == nullptr || c.directory.native().size() > owner->directory.native().size()) {
      owner = &c;
      relative = r;
    }
  }
  if (owner == nullptr) return;
  const std::string line = relative.generic_string();
  if (line == kOutputListName || !owner->listed.insert(line).second) return;
  append_to_list(owner->directory, line);
}

std::vector<fs::path> remove_own_temporary_files() {
  std::vector<fs::path> directories;
  {
    const std::lock_guard lock(claims_mutex());
    for (const Claim& c : claims()) directories.push_back(c.directory);
  }
  std::vector<fs::path> files;
  for (const fs::path& d : directories) collect_temporary_files(d, 0, true, files);
  std::sort(files.begin(), files.end());
  files.erase(std::unique(files.begin(), files.end()), files.end());
  return remove_files(files);
}

}  // namespace pilempm
