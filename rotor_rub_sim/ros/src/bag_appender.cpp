#include "rotor_rub_sim/ros/bag_appender.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

// The layout written here is rosbag format 2.0 (http://wiki.ros.org/Bags/Format/2.0):
//   "#ROSBAG V2.0\n"
//   file header record, padded to 4096 bytes      (rewritten by close())
//   { chunk record (connection + message data records),
//     one index data record per connection in the chunk } ...
//   connection records, chunk info records         (written by close())
// A record is: uint32 header length, header fields (uint32 length,
// "name=value"), uint32 data length, data. Integers are little-endian, as
// rosbag writes them on the machines ROS runs on.

namespace rotor_rub::ros_node {
namespace {

constexpr char kVersionLine[] = "#ROSBAG V2.0\n";
constexpr uint64_t kFileHeaderPosition = sizeof(kVersionLine) - 1;
constexpr uint32_t kFileHeaderLength = 4096;  // rosbag's FILE_HEADER_LENGTH
constexpr uint8_t kOpMessageData = 0x02, kOpFileHeader = 0x03, kOpIndexData = 0x04, kOpChunk = 0x05,
                  kOpChunkInfo = 0x06, kOpConnection = 0x07;
constexpr uint32_t kIndexVersion = 1, kChunkInfoVersion = 1;

using Bytes = std::vector<uint8_t>;

void put(Bytes& out, const void* p, size_t n) {
  const auto* b = static_cast<const uint8_t*>(p);
  out.insert(out.end(), b, b + n);
}
template <class T>
void put_value(Bytes& out, T v) {
  put(out, &v, sizeof v);
}
void put_time(Bytes& out, const ros::Time& t) {
  put_value<uint32_t>(out, t.sec);
  put_value<uint32_t>(out, t.nsec);
}
void put_field(Bytes& out, const char* name, const void* value, size_t n) {
  const size_t name_len = std::strlen(name);
  put_value<uint32_t>(out, static_cast<uint32_t>(name_len + 1 + n));
  put(out, name, name_len);
  out.push_back('=');
  put(out, value, n);
}
template <class T>
void put_field_value(Bytes& out, const char* name, T v) {
  put_field(out, name, &v, sizeof v);
}
void put_field_time(Bytes& out, const char* name, const ros::Time& t) {
  const uint32_t v[2] = {t.sec, t.nsec};
  put_field(out, name, v, sizeof v);
}
void put_field_string(Bytes& out, const char* name, const std::string& s) { put_field(out, name, s.data(), s.size()); }
// A header is its fields behind their total length.
void put_header(Bytes& out, const Bytes& fields) {
  put_value<uint32_t>(out, static_cast<uint32_t>(fields.size()));
  put(out, fields.data(), fields.size());
}

}  // namespace

BagAppender::~BagAppender() {
  try {
    close();
  } catch (const std::exception&) {
    // Nothing to report to from a destructor; the chunks already on disk
    // stay readable after `rosbag reindex`.
  }
}

void BagAppender::open(const std::string& path, size_t chunk_bytes) {
  close();
  path_ = path;
  chunk_bytes_ = std::max<size_t>(chunk_bytes, 1);
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) throw std::runtime_error("cannot create '" + path + "': " + std::strerror(errno));
  file_position_ = 0;
  connections_.clear();
  chunks_.clear();
  chunk_.clear();
  chunk_messages_ = 0;
  chunk_.reserve(chunk_bytes_ + 64 * 1024);
  messages_written_ = 0;
  write_bytes(kVersionLine, kFileHeaderPosition);
  write_file_header(0);                        // index position 0 marks the bag unindexed until close()
  if (std::fflush(file_) != 0) fail("flush");  // a valid (empty) bag from the start
}

uint32_t BagAppender::connection_id(const std::string& topic, const char* datatype, const char* md5sum,
                                    const char* definition, bool latching) {
  // A handful of topics: a linear scan beats hashing the topic name.
  for (size_t i = 0; i < connections_.size(); ++i) {
    if (connections_[i].topic == topic) return static_cast<uint32_t>(i);
  }
  Connection c;
  c.topic = topic;
  c.datatype = datatype;
  c.md5sum = md5sum;
  c.definition = definition;
  c.latching = latching;
  connections_.push_back(std::move(c));
  return static_cast<uint32_t>(connections_.size() - 1);
}

void BagAppender::append_connection_record(Bytes& out, uint32_t id) const {
  const Connection& c = connections_[id];
  Bytes fields;
  put_field_value<uint8_t>(fields, "op", kOpConnection);
  put_field_string(fields, "topic", c.topic);
  put_field_value<uint32_t>(fields, "conn", id);
  put_header(out, fields);
  // The data is the connection header, the same fields a subscriber gets.
  Bytes connection_header;
  put_field_string(connection_header, "topic", c.topic);
  put_field_string(connection_header, "type", c.datatype);
  put_field_string(connection_header, "md5sum", c.md5sum);
  put_field_string(connection_header, "message_definition", c.definition);
  if (c.latching) put_field_string(connection_header, "latching", "1");
  put_header(out, connection_header);
}

void BagAppender::begin_message(uint32_t conn, const ros::Time& t, uint32_t data_bytes) {
  if (file_ == nullptr) throw std::runtime_error("bag not open");
  if (t < ros::TIME_MIN) throw std::runtime_error("bag time before ros::TIME_MIN");
  Connection& c = connections_[conn];
  if (!c.record_written) {
    append_connection_record(chunk_, conn);  // inside the chunk, as rosbag does
    c.record_written = true;
  }
  if (chunk_messages_++ == 0) {
    chunk_start_ = chunk_end_ = t;
  } else {
    chunk_start_ = std::min(chunk_start_, t);
    chunk_end_ = std::max(chunk_end_, t);
  }
  if (!c.chunk_index.empty() && t < c.chunk_index.back().time) c.sorted = false;
  c.chunk_index.push_back({t, static_cast<uint32_t>(chunk_.size())});
  // Message data record header: op, conn, time (fixed size; built inline
  // because this runs once per message).
  Bytes& out = chunk_;
  put_value<uint32_t>(out, 4 + 4 + 4 + 9 + 4 + 13);
  put_field_value<uint8_t>(out, "op", kOpMessageData);
  put_field_value<uint32_t>(out, "conn", conn);
  put_field_time(out, "time", t);
  put_value<uint32_t>(out, data_bytes);
  out.resize(out.size() + data_bytes);
}

void BagAppender::end_message() {
  ++messages_written_;
  if (chunk_.size() >= chunk_bytes_) write_chunk();
}

void BagAppender::flush() {
  if (file_ == nullptr) return;
  write_chunk();
  if (std::fflush(file_) != 0) fail("flush");
}

void BagAppender::write_chunk() {
  if (chunk_.empty()) return;
  ChunkInfo info{file_position_, chunk_start_, chunk_end_, {}};
  Bytes head;
  {
    Bytes fields;
    put_field_string(fields, "compression", "none");
    put_field_value<uint8_t>(fields, "op", kOpChunk);
    put_field_value<uint32_t>(fields, "size", static_cast<uint32_t>(chunk_.size()));
    put_header(head, fields);
    put_value<uint32_t>(head, static_cast<uint32_t>(chunk_.size()));  // stored uncompressed
  }
  write_bytes(head.data(), head.size());
  write_bytes(chunk_.data(), chunk_.size());
  Bytes index;
  for (size_t id = 0; id < connections_.size(); ++id) {
    Connection& c = connections_[id];
    if (c.chunk_index.empty()) continue;
    // Readers bisect the index by time; entries go out in time order.
    if (!c.sorted) {
      std::stable_sort(c.chunk_index.begin(), c.chunk_index.end(),
                       [](const IndexEntry& a, const IndexEntry& b) { return a.time < b.time; });
    }
    const auto count = static_cast<uint32_t>(c.chunk_index.size());
    Bytes fields;
    put_field_value<uint8_t>(fields, "op", kOpIndexData);
    put_field_value<uint32_t>(fields, "ver", kIndexVersion);
    put_field_value<uint32_t>(fields, "conn", static_cast<uint32_t>(id));
    put_field_value<uint32_t>(fields, "count", count);
    put_header(index, fields);
    put_value<uint32_t>(index, count * 12);
    for (const IndexEntry& e : c.chunk_index) {
      put_time(index, e.time);
      put_value<uint32_t>(index, e.offset);
    }
    info.counts.emplace_back(static_cast<uint32_t>(id), count);
    c.chunk_index.clear();
    c.sorted = true;
  }
  write_bytes(index.data(), index.size());
  chunks_.push_back(std::move(info));
  chunk_.clear();
  chunk_messages_ = 0;
  // A complete chunk goes to the kernel at once: it survives a kill.
  if (std::fflush(file_) != 0) fail("flush");
}

void BagAppender::close() {
  if (file_ == nullptr) return;
  write_chunk();
  const uint64_t index_position = file_position_;
  Bytes tail;
  for (uint32_t id = 0; id < connections_.size(); ++id) append_connection_record(tail, id);
  for (const ChunkInfo& info : chunks_) {
    Bytes fields;
    put_field_value<uint8_t>(fields, "op", kOpChunkInfo);
    put_field_value<uint32_t>(fields, "ver", kChunkInfoVersion);
    put_field_value<uint64_t>(fields, "chunk_pos", info.position);
    put_field_time(fields, "start_time", info.start);
    put_field_time(fields, "end_time", info.end);
    put_field_value<uint32_t>(fields, "count", static_cast<uint32_t>(info.counts.size()));
    put_header(tail, fields);
    put_value<uint32_t>(tail, static_cast<uint32_t>(info.counts.size() * 8));
    for (const auto& [id, count] : info.counts) {
      put_value<uint32_t>(tail, id);
      put_value<uint32_t>(tail, count);
    }
  }
  write_bytes(tail.data(), tail.size());
  if (std::fseek(file_, static_cast<long>(kFileHeaderPosition), SEEK_SET) != 0) fail("seek to the file header");
  file_position_ = kFileHeaderPosition;
  write_file_header(index_position);
  std::FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) throw std::runtime_error("cannot close '" + path_ + "': " + std::strerror(errno));
}

void BagAppender::write_file_header(uint64_t index_position) {
  Bytes fields;
  put_field_value<uint8_t>(fields, "op", kOpFileHeader);
  put_field_value<uint64_t>(fields, "index_pos", index_position);
  put_field_value<uint32_t>(fields, "conn_count", static_cast<uint32_t>(connections_.size()));
  put_field_value<uint32_t>(fields, "chunk_count", static_cast<uint32_t>(chunks_.size()));
  Bytes record;
  put_header(record, fields);
  // Padded with spaces so close() can rewrite it in place (as rosbag does).
  const uint32_t padding = kFileHeaderLength - static_cast<uint32_t>(fields.size());
  put_value<uint32_t>(record, padding);
  record.resize(record.size() + padding, ' ');
  write_bytes(record.data(), record.size());
}

void BagAppender::write_bytes(const void* data, size_t n) {
  if (n == 0) return;
  if (std::fwrite(data, 1, n, file_) != n) fail("write");
  file_position_ += n;
}

void BagAppender::fail(const std::string& what) {
  throw std::runtime_error("bag '" + path_ + "': " + what + " failed: " + std::strerror(errno));
}

}  // namespace rotor_rub::ros_node
