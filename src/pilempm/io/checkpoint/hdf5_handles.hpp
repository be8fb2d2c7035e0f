#pragma once
// HDF5 for the MPM checkpoint (io/mpm_checkpoint.hpp): handles that close themselves, HDF5's
// error stack kept quiet and read back as text, and the content checksum of the datasets.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pilempm::checkpoint {

// Owns one hid_t and closes it with the function its kind needs.
class Handle {
 public:
  using Close = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Close closer) : id_(id), close_(closer) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept
      : id_(std::exchange(other.id_, H5I_INVALID_HID)), close_(other.close_) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
      close_ = other.close_;
    }
    return *this;
  }
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  /// Closes now; false when the close failed (for a file: its data may not all be written).
  bool close() {
    if (!valid()) return true;
    const herr_t status = close_(id_);
    id_ = H5I_INVALID_HID;
    return status >= 0;
  }

 private:
  void reset() {
    if (valid()) close_(id_);
    id_ = H5I_INVALID_HID;
  }
  hid_t id_ = H5I_INVALID_HID;
  Close close_ = nullptr;
};

// Turns off HDF5's printing of its error stack for the lifetime of the object (the errors are
// reported as exceptions instead) and restores what was set before.
class QuietHdf5Errors {
 public:
  QuietHdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  QuietHdf5Errors(const QuietHdf5Errors&) = delete;
  QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;
  ~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }

 private:
  H5E_auto2_t function_ = nullptr;
  void* data_ = nullptr;
};

// The innermost message on HDF5's error stack (what went wrong at the bottom), or "".
std::string hdf5_error_text();

// The 64-bit FNV-1a hash of `size` bytes (Fowler, Noll and Vo; offset basis and prime of the
// published 64-bit variant). Any change of one byte changes it.
std::uint64_t content_hash(const void* data, std::size_t size);

// The bytes of a dataset of `dims` in memory type `memory_type`.
std::size_t byte_count(hid_t memory_type, const std::vector<hsize_t>& dims);

// A fixed-length string type of `size` bytes (at least 1), padded with NULs.
Handle string_type(std::size_t size);

}  // namespace pilempm::checkpoint
