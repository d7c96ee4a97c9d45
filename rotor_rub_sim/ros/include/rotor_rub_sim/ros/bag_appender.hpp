// An append-only writer of rosbag format 2.0 files, for recording inside the
// node at thousands of messages per simulated second.
//
// Why not rosbag::Bag: its write() seeks to the end of the file before every
// message (in case the previous operation was a read), which flushes the
// stdio buffer: four system calls per message, which held the node's
// real-time factor down at a 10 kHz state rate (docs/benchmarks.md, "The
// node"). This writer never reads, so it never seeks while
// recording: messages are serialised into an in-memory chunk, and a chunk
// goes to the file whole (chunk record, then its index records) when it
// reaches chunk_bytes or when flush() is called. close() appends the
// connection and chunk-info records and fills in the file header, exactly as
// rosbag::Bag lays the file out, so rosbag, rqt_bag and the Python API read
// it unchanged.
//
// Crash contract: every chunk on disk is complete. A process killed before
// close() leaves an unindexed bag holding every message up to the last flush
// (or full chunk); `rosbag reindex` makes it readable. The caller bounds the
// loss by calling flush() periodically.
#pragma once

#include <ros/message_traits.h>
#include <ros/serialization.h>
#include <ros/time.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace rotor_rub::ros_node {

class BagAppender {
 public:
  // rosbag::Bag's default chunk threshold: readers load one chunk at a time.
  static constexpr size_t kDefaultChunkBytes = 768 * 1024;

  BagAppender() = default;
  ~BagAppender();  // closes (indexes) the bag; errors there are swallowed
  BagAppender(const BagAppender&) = delete;
  BagAppender& operator=(const BagAppender&) = delete;

  // Creates (truncates) path. Throws std::runtime_error naming the path.
  void open(const std::string& path, size_t chunk_bytes = kDefaultChunkBytes);
  bool is_open() const { return file_ != nullptr; }
  const std::string& path() const { return path_; }

  // Appends msg on topic at time t (t >= ros::TIME_MIN, as rosbag requires).
  // latching marks the connection so that `rosbag play` re-latches it.
  // Throws std::runtime_error on a write failure or a time before TIME_MIN.
  template <class Msg>
  void write(const std::string& topic, const ros::Time& t, const Msg& msg, bool latching = false);

  // Writes the open chunk, if any, and hands it to the kernel (fflush, not
  // fsync: it survives the process being killed, not the machine failing).
  void flush();
  // Writes the index and the file header and closes the file. Idempotent.
  void close();

  uint64_t messages_written() const { return messages_written_; }

 private:
  struct IndexEntry {
    ros::Time time;
    uint32_t offset;  // of the message data record within the chunk data
  };
  struct Connection {
    std::string topic;
    std::string datatype, md5sum, definition;
    bool latching = false;
    bool record_written = false;          // its connection record is in a chunk already
    std::vector<IndexEntry> chunk_index;  // this chunk's entries
    bool sorted = true;                   // chunk_index is in time order
  };
  struct ChunkInfo {
    uint64_t position;
    ros::Time start, end;
    std::vector<std::pair<uint32_t, uint32_t>> counts;  // (connection id, messages)
  };

  uint32_t connection_id(const std::string& topic, const char* datatype, const char* md5sum, const char* definition,
                         bool latching);
  void begin_message(uint32_t conn, const ros::Time& t, uint32_t data_bytes);
  void end_message();
  void write_chunk();
  void write_bytes(const void* data, size_t n);
  void write_file_header(uint64_t index_position);
  void append_connection_record(std::vector<uint8_t>& out, uint32_t id) const;
  void fail(const std::string& what);

  std::string path_;
  std::FILE* file_ = nullptr;
  size_t chunk_bytes_ = kDefaultChunkBytes;
  uint64_t file_position_ = 0;
  std::vector<uint8_t> chunk_;  // the open chunk's data
  uint32_t chunk_messages_ = 0;
  ros::Time chunk_start_, chunk_end_;  // the open chunk's earliest and latest message
  std::vector<Connection> connections_;
  std::vector<ChunkInfo> chunks_;
  uint64_t messages_written_ = 0;
};

template <class Msg>
void BagAppender::write(const std::string& topic, const ros::Time& t, const Msg& msg, bool latching) {
  namespace mt = ros::message_traits;
  const uint32_t conn = connection_id(topic, mt::DataType<Msg>::value(), mt::MD5Sum<Msg>::value(),
                                      mt::Definition<Msg>::value(), latching);
  const uint32_t n = ros::serialization::serializationLength(msg);
  begin_message(conn, t, n);
  // begin_message grew chunk_ by n bytes at the end: serialise in place.
  ros::serialization::OStream stream(chunk_.data() + chunk_.size() - n, n);
  ros::serialization::serialize(stream, msg);
  end_message();
}

}  // namespace rotor_rub::ros_node
