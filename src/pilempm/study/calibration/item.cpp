#include "pilempm/study/calibration/item.hpp"

#include <fmt/format.h>

#include <utility>
#include <variant>

#include "pilempm/core/error.hpp"
#include "pilempm/io/output/atomic_file.hpp"

namespace pilempm::study::calibration {

TestResults::TestResults(const std::vector<ElementRunRecord>& records) : records_(records) {
  for (std::size_t i = 0; i < records_.size(); ++i) index_.emplace(records_[i].test->name, i);
}

const ElementRunRecord& TestResults::record(std::string_view name) const {
  const auto it = index_.find(name);
  if (it == index_.end()) throw Error(fmt::format("the study's case has no test \"{}\"", name));
  const ElementRunRecord& r = records_[it->second];
  if (!r.ok) throw Error(fmt::format("element test {} failed: {}", name, r.error));
  return r;
}

double TestResults::sigma3(std::string_view name) const {
  const auto* t = std::get_if<DrainedTriaxialTest>(&test(name).test);
  if (t == nullptr) throw Error(fmt::format("study test {} is not a drained triaxial", name));
  return t->sigma3;
}

ItemOutput::ItemOutput(std::filesystem::path out_dir, StudyItem& item, Progress progress)
    : out_dir_(std::move(out_dir)), item_(item), progress_(std::move(progress)) {}

void ItemOutput::write_csv(const std::string& file, const std::string& text) {
  write_file_atomically(out_dir_ / file, text);
  item_.csv.push_back(file);
  if (progress_) progress_(fmt::format("  wrote {}", (out_dir_ / file).string()));
}

void ItemOutput::add_figure(FigureSpec figure) {
  item_.png.push_back(figure.file);
  figures_.push_back(std::move(figure));
}

}  // namespace pilempm::study::calibration
