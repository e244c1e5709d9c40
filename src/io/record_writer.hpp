// SPDX-License-Identifier: MIT
#pragma once
/// @file Records of a time series written into an HDF5 file by a background thread.
///
/// One record is a set of small arrays, each written as its own dataset `/<field>/<record>`
/// (the layout every XDMF reader reads, see python/slidebeam/xdmf.py). Creating an HDF5 object
/// costs about 8 us, a record of 15 fields more than a small scene's time step; the thread does
/// it while the run goes on. `add` copies the arrays and returns at once; `wait` blocks until
/// every record handed over is written and the file flushed, and reports the first failure.
///
/// Only this thread calls the HDF5 library it is linked with (the MPI build PETSc uses) while
/// records are pending: a caller that uses PETSc's HDF5 viewer (the checkpoint) waits first.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace slidebeam::io {

/// One array of a record: `rows` x `cols` values (cols 1: a vector), float64 or int32.
struct RecordField {
  std::string name;  ///< the group it goes to
  std::vector<std::int64_t> shape;
  bool is_int = false;
  std::vector<unsigned char> bytes;
};

class RecordWriter {
 public:
  /// Open an existing HDF5 file (its mesh is written) for appending records.
  /// `compact_bytes`: datasets up to this size live in their object header.
  explicit RecordWriter(const std::string& path, std::size_t compact_bytes = 32 << 10);
  ~RecordWriter();
  RecordWriter(const RecordWriter&) = delete;
  RecordWriter& operator=(const RecordWriter&) = delete;

  /// Hand over record `record`'s fields (written as /<field>/<record>). After a failure the
  /// records are dropped; `wait` reports it.
  void add(long record, std::vector<RecordField> fields);
  /// After the records handed over so far: flush the file, then write `text` into the text file
  /// set by set_text_file at its current end mark, followed by `tail`, and move the mark past
  /// `text` (the XDMF steps of those records, appended over the closing tags). Returns at once.
  void append_text(std::string text);
  /// The file append_text writes into, and the offset of its end mark (where its closing tags
  /// `tail` begin). end_mark 0: the file is created (beside it, then renamed) at the first
  /// append_text, as head + text + tail.
  void set_text_file(const std::string& path, std::uint64_t end_mark, const std::string& tail,
                     const std::string& head = "");
  /// Block until every record and text handed over is written and the file flushed. Returns
  /// the first failure's message ("" if none).
  std::string wait();
  /// The first failure's message so far ("" if none), without waiting.
  std::string error() const;
  /// wait(), then close the file (left open after a failure: HDF5 may crash closing it).
  std::string close();
  /// The record whose writing failed first, -1 if none.
  long failed_record() const;
  /// Records handed over and not yet written.
  std::size_t pending() const;

 private:
  struct Record {
    long index;
    std::vector<RecordField> fields;
    bool is_text = false;  // a text to append (after a flush), not a record
    std::string text;
  };
  void write_text(const std::string& text);
  void run();
  void write(const Record& r);
  void check_room(const Record& r) const;
  /// Room kept free beyond a record's values: its objects' headers and links, and the metadata
  /// HDF5 holds in its cache until the next flush.
  static constexpr std::uint64_t kBytesPerDataset = 1024;
  static constexpr std::uint64_t kMetadataReserve = 4u << 20;
  /// Records queued before the thread is woken: a wake-up costs the caller more than a copy.
  static constexpr std::size_t kWakeAfter = 16;
  static constexpr std::size_t kMetadataCacheBytes = 256 << 10;
  std::int64_t group(const std::string& name);

  std::int64_t file_ = -1;  // hid_t
  int fd_ = -1;  // its descriptor, for the free space
  std::int64_t dcpl_compact_ = -1, dcpl_contiguous_ = -1;
  std::size_t compact_bytes_;
  std::map<std::string, std::int64_t> groups_;

  mutable std::mutex mutex_;
  std::condition_variable work_, idle_;
  std::deque<Record> queue_;
  bool busy_ = false, flush_ = false, stop_ = false;
  std::string error_;
  long failed_record_ = -1;
  std::string text_path_, tail_, head_;
  std::uint64_t text_end_ = 0;
  std::thread thread_;
};

}  // namespace slidebeam::io
