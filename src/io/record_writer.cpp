// SPDX-License-Identifier: MIT
#include "io/record_writer.hpp"

#include <hdf5.h>

#include <sys/resource.h>
#include <sys/statvfs.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace slidebeam::io {

namespace {

/// The HDF5 error stack as one line: the outermost failure, and the system's reason (a full
/// disk, a file size limit) where the innermost entry names one.
herr_t collect(unsigned n, const H5E_error2_t* e, void* data) {
  auto* lines = static_cast<std::vector<std::string>*>(data);
  (void)n;
  lines->emplace_back(e->desc ? e->desc : "");
  return 0;
}

std::string error_stack(const std::string& what) {
  std::vector<std::string> lines;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collect, &lines);
  H5Eclear2(H5E_DEFAULT);
  std::string message = what;
  if (!lines.empty() && !lines.front().empty()) message += ": " + lines.front();
  for (const auto& line : lines) {
    const auto at = line.find("error message = '");
    if (at == std::string::npos) continue;
    const auto start = at + 17, end = line.find('\'', start);
    message += " (" + line.substr(start, end == std::string::npos ? std::string::npos : end - start) + ")";
    break;
  }
  return message;
}

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error(error_stack(what));
}

hid_t checked(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error(error_stack(what));
  return id;
}

/// The HDF5 library is not built thread-safe: the writers of several series (each with its
/// thread) take turns.
std::mutex& library_lock() {
  static std::mutex lock;
  return lock;
}

/// HDF5 prints its error stack to stderr unless told not to; the writer reports failures
/// itself. The previous handler is restored for the other users of the library (PETSc).
class QuietErrors {
 public:
  QuietErrors() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

}  // namespace

RecordWriter::RecordWriter(const std::string& path, std::size_t compact_bytes) : compact_bytes_(compact_bytes) {
  std::lock_guard<std::mutex> library(library_lock());
  QuietErrors quiet;
  // No file lock: a reader (ParaView, a script, this process's h5py) may open the series while
  // the run goes on; the .xdmf only names records whose data is flushed.
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_file_locking(fapl, false, true);
  // A small metadata cache: the records' object headers leave it as the writer goes (on its
  // thread), not all at once when the file is closed at the end of the run.
  H5AC_cache_config_t cache;
  cache.version = H5AC__CURR_CACHE_CONFIG_VERSION;
  if (H5Pget_mdc_config(fapl, &cache) >= 0) {
    cache.set_initial_size = true;
    cache.initial_size = kMetadataCacheBytes;
    cache.max_size = kMetadataCacheBytes;
    cache.min_size = std::min<std::size_t>(cache.min_size, kMetadataCacheBytes);
    H5Pset_mdc_config(fapl, &cache);
  }
  file_ = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl);
  H5Pclose(fapl);
  if (file_ < 0) throw std::runtime_error(error_stack("cannot open " + path));
  void* handle = nullptr;
  if (H5Fget_vfd_handle(file_, H5P_DEFAULT, &handle) >= 0 && handle) fd_ = *static_cast<int*>(handle);
  // no time stamps: the same run writes the same bytes
  dcpl_compact_ = H5Pcreate(H5P_DATASET_CREATE);
  dcpl_contiguous_ = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_obj_track_times(dcpl_compact_, 0);
  H5Pset_obj_track_times(dcpl_contiguous_, 0);
  H5Pset_layout(dcpl_compact_, H5D_COMPACT);
  thread_ = std::thread([this] { run(); });
}

RecordWriter::~RecordWriter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_.notify_one();
  if (thread_.joinable()) thread_.join();
  if (file_ >= 0) close();
}

void RecordWriter::add(long record, std::vector<RecordField> fields) {
  bool wake = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_.empty() || file_ < 0) return;
    queue_.push_back(Record{record, std::move(fields)});
    wake = queue_.size() >= kWakeAfter;
  }
  if (wake) work_.notify_one();
}

void RecordWriter::set_text_file(const std::string& path, std::uint64_t end_mark, const std::string& tail,
                                 const std::string& head) {
  std::lock_guard<std::mutex> lock(mutex_);
  text_path_ = path;
  text_end_ = end_mark;
  tail_ = tail;
  head_ = head;
}

void RecordWriter::append_text(std::string text) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_.empty() || file_ < 0) return;
    Record r{-1, {}, true, std::move(text)};
    queue_.push_back(std::move(r));
  }
  work_.notify_one();
}

std::string RecordWriter::error() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return error_;
}

void RecordWriter::write_text(const std::string& text) {
  {
    std::lock_guard<std::mutex> library(library_lock());
    QuietErrors quiet;
    if (H5Fflush(file_, H5F_SCOPE_LOCAL) < 0) throw std::runtime_error(error_stack("flushing the file failed"));
  }
  if (text_end_ == 0) {  // the file's first text: written beside it and renamed, whole
    const std::string tmp = text_path_ + ".tmp";
    const std::string data = head_ + text + tail_;
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (fd < 0) throw std::runtime_error("cannot create " + tmp + " (" + std::strerror(errno) + ")");
    const ssize_t written = ::write(fd, data.data(), data.size());
    const int err = errno;
    ::close(fd);
    if (written != static_cast<ssize_t>(data.size()) || std::rename(tmp.c_str(), text_path_.c_str()) != 0)
      throw std::runtime_error("cannot write " + text_path_ + " (" + std::strerror(written < 0 ? err : errno) + ")");
    text_end_ = head_.size() + text.size();
    return;
  }
  // one write over the closing tags: the document on disk ends complete before and after
  const std::string data = text + tail_;
  const int fd = ::open(text_path_.c_str(), O_WRONLY);
  if (fd < 0) throw std::runtime_error("cannot open " + text_path_ + " (" + std::strerror(errno) + ")");
  const ssize_t written = ::pwrite(fd, data.data(), data.size(), static_cast<off_t>(text_end_));
  const int err = errno;
  ::close(fd);
  if (written != static_cast<ssize_t>(data.size()))
    throw std::runtime_error("cannot write " + text_path_ + " (" + (written < 0 ? std::strerror(err) : "short write") + ")");
  text_end_ += text.size();
}

std::string RecordWriter::wait() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!thread_.joinable()) return error_;
  flush_ = true;
  work_.notify_one();
  idle_.wait(lock, [this] { return queue_.empty() && !busy_ && !flush_; });
  return error_;
}

std::string RecordWriter::close() {
  std::string error = wait();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_.notify_one();
  if (thread_.joinable()) thread_.join();
  if (file_ < 0) return error;
  std::lock_guard<std::mutex> library(library_lock());
  QuietErrors quiet;
  for (auto& [name, id] : groups_) H5Gclose(id);
  groups_.clear();
  H5Pclose(dcpl_compact_);
  H5Pclose(dcpl_contiguous_);
  const herr_t status = H5Fclose(file_);
  file_ = -1;
  if (status < 0 && error.empty()) error = error_stack("closing the file failed");
  return error;
}

long RecordWriter::failed_record() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failed_record_;
}

std::size_t RecordWriter::pending() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return queue_.size() + (busy_ ? 1 : 0);
}

void RecordWriter::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_.wait(lock, [this] {
      return stop_ || flush_ || queue_.size() >= kWakeAfter || (!queue_.empty() && queue_.back().is_text);
    });
    while (!queue_.empty()) {  // once awake, the whole queue
      Record record = std::move(queue_.front());
      queue_.pop_front();
      busy_ = true;
      const bool failed = !error_.empty();
      lock.unlock();
      std::string error;
      if (!failed) {
        try {
          if (record.is_text)
            write_text(record.text);
          else
            write(record);
        } catch (const std::exception& e) {
          error = e.what();
        }
      }
      lock.lock();
      busy_ = false;
      if (!error.empty() && error_.empty()) {
        error_ = error;
        failed_record_ = record.index;
      }
    }
    if (flush_) {
      if (error_.empty()) {
        lock.unlock();
        std::string error;
        {
          std::lock_guard<std::mutex> library(library_lock());
          QuietErrors quiet;
          if (H5Fflush(file_, H5F_SCOPE_LOCAL) < 0) error = error_stack("flushing the file failed");
        }
        lock.lock();
        if (!error.empty() && error_.empty()) error_ = error;
      }
      if (queue_.empty()) {
        flush_ = false;
        idle_.notify_all();
      }
      continue;
    }
    if (stop_) return;
  }
}

std::int64_t RecordWriter::group(const std::string& name) {
  auto it = groups_.find(name);
  if (it != groups_.end()) return it->second;
  const htri_t exists = H5Lexists(file_, name.c_str(), H5P_DEFAULT);
  check(exists, "cannot look up /" + name);
  const hid_t id = exists > 0 ? H5Gopen2(file_, name.c_str(), H5P_DEFAULT)
                              : H5Gcreate2(file_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  return groups_[name] = checked(id, "cannot create the group /" + name);
}

void RecordWriter::check_room(const Record& r) const {
  // HDF5 cannot close a file whose metadata it failed to write (it crashes at exit), so a record
  // that would not fit is refused before HDF5 sees it: the file stays whole, its records readable.
  std::uint64_t bytes = kMetadataReserve;
  for (const auto& f : r.fields) bytes += f.bytes.size() + kBytesPerDataset;
  hsize_t size = 0;
  if (H5Fget_filesize(file_, &size) < 0) size = 0;
  rlimit limit{};
  if (getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY && size + bytes > limit.rlim_cur)
    throw std::runtime_error(std::string("the record would not fit (") + std::strerror(EFBIG) + ")");
  struct statvfs disk {};
  if (fstatvfs(fd_, &disk) == 0 && static_cast<std::uint64_t>(disk.f_bavail) * disk.f_frsize < bytes)
    throw std::runtime_error(std::string("the record would not fit (") + std::strerror(ENOSPC) + ")");
}

void RecordWriter::write(const Record& r) {
  std::lock_guard<std::mutex> library(library_lock());
  QuietErrors quiet;
  check_room(r);
  const std::string name = std::to_string(r.index);
  for (const auto& f : r.fields) {
    const hid_t g = group(f.name);
    std::vector<hsize_t> dims(f.shape.begin(), f.shape.end());
    const hid_t space = checked(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                                "cannot describe /" + f.name + "/" + name);
    const hid_t dcpl = f.bytes.size() <= compact_bytes_ ? dcpl_compact_ : dcpl_contiguous_;
    const hid_t set = H5Dcreate2(g, name.c_str(), f.is_int ? H5T_STD_I32LE : H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                 dcpl, H5P_DEFAULT);
    if (set < 0) {  // read the error stack before another call clears it
      const std::string message = error_stack("cannot create /" + f.name + "/" + name);
      H5Sclose(space);
      throw std::runtime_error(message);
    }
    H5Sclose(space);
    const herr_t status = H5Dwrite(set, f.is_int ? H5T_NATIVE_INT32 : H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL,
                                   H5P_DEFAULT, f.bytes.data());
    if (status < 0) {
      const std::string message = error_stack("cannot write /" + f.name + "/" + name);
      H5Dclose(set);
      throw std::runtime_error(message);
    }
    check(H5Dclose(set), "cannot write /" + f.name + "/" + name);
  }
}

}  // namespace slidebeam::io
