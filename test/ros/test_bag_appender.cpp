// BagAppender writes bags that rosbag's own reader reads back exactly: every
// message, its topic, time, type and payload, across chunk boundaries, with
// out-of-order times and latched connections. No master needed.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "rotor_rub_msgs/RotorState.h"
#include "rotor_rub_sim/ros/bag_appender.hpp"

using rotor_rub::ros_node::BagAppender;

namespace {

std::string temp_path(const std::string& name) {
  return testing::TempDir() + name + "." + std::to_string(::getpid()) + ".bag";
}

rotor_rub_msgs::RotorState state(uint64_t i) {
  rotor_rub_msgs::RotorState m;
  m.sample_index = i;
  m.header.frame_id = "world";
  m.rotor_position.x = 1e-4 * static_cast<double>(i);
  m.normal_force = 3.0 * static_cast<double>(i);
  m.in_contact = (i % 3 == 0);
  return m;
}

ros::Time at(double t_s) { return ros::Time().fromSec(t_s); }

struct Written {
  std::string topic;
  ros::Time time;
  uint64_t index;
};

// Writes a fixed message sequence with both writers.
template <class Writer>
std::vector<Written> write_sequence(Writer& bag) {
  std::vector<Written> out;
  for (uint64_t i = 0; i < 500; ++i) {
    const ros::Time t = std::max(at(1e-4 * static_cast<double>(i)), ros::TIME_MIN);
    const std::string topic = (i % 5 == 0) ? "/sim/contact_like" : "/sim/state";
    bag.write(topic, t, state(i));
    out.push_back({topic, t, i});
  }
  std_msgs::String late;
  late.data = "written last, stamped early";
  bag.write("/sim/note", at(0.00105), late);  // between two state times
  return out;
}

}  // namespace

TEST(BagAppender, RosbagReadsEveryMessageBackAcrossChunks) {
  const std::string path = temp_path("appender");
  {
    BagAppender bag;
    bag.open(path, /*chunk_bytes=*/4096);  // small chunks: many chunk boundaries
    write_sequence(bag);
    EXPECT_EQ(bag.messages_written(), 501u);
  }  // the destructor closes (indexes) the bag

  const std::string ref_path = temp_path("rosbag_reference");
  std::vector<Written> expected;
  {
    rosbag::Bag ref(ref_path, rosbag::bagmode::Write);
    expected = write_sequence(ref);
  }

  rosbag::Bag mine(path, rosbag::bagmode::Read);
  rosbag::Bag ref(ref_path, rosbag::bagmode::Read);
  rosbag::View mine_view(mine), ref_view(ref);
  ASSERT_EQ(mine_view.size(), 501u);
  ASSERT_EQ(mine_view.size(), ref_view.size());
  EXPECT_EQ(mine_view.getBeginTime(), ref_view.getBeginTime());
  EXPECT_EQ(mine_view.getEndTime(), ref_view.getEndTime());
  // Both readers order by time; equal times keep the connection order, which
  // both writers assign the same way (first use).
  auto a = mine_view.begin();
  auto b = ref_view.begin();
  for (; a != mine_view.end() && b != ref_view.end(); ++a, ++b) {
    ASSERT_EQ(a->getTopic(), b->getTopic());
    ASSERT_EQ(a->getTime(), b->getTime());
    ASSERT_EQ(a->getDataType(), b->getDataType());
    ASSERT_EQ(a->getMD5Sum(), b->getMD5Sum());
    ASSERT_EQ(a->getMessageDefinition(), b->getMessageDefinition());
    ASSERT_EQ(a->size(), b->size());
    if (a->getDataType() == "rotor_rub_msgs/RotorState") {
      const auto ma = a->instantiate<rotor_rub_msgs::RotorState>();
      const auto mb = b->instantiate<rotor_rub_msgs::RotorState>();
      ASSERT_TRUE(ma && mb);
      EXPECT_EQ(ma->sample_index, mb->sample_index);
      EXPECT_EQ(ma->rotor_position.x, mb->rotor_position.x);  // bit-exact: same bytes
      EXPECT_EQ(ma->normal_force, mb->normal_force);
      EXPECT_EQ(ma->in_contact, mb->in_contact);
    } else {
      EXPECT_EQ(a->instantiate<std_msgs::String>()->data, "written last, stamped early");
    }
  }
  // A time-range query uses the chunk infos and index records.
  rosbag::View window(mine, rosbag::TopicQuery("/sim/state"), at(0.01), at(0.02));
  size_t n = 0;
  for (const auto& m : window) {
    EXPECT_GE(m.getTime(), at(0.01));
    EXPECT_LE(m.getTime(), at(0.02));
    ++n;
  }
  rosbag::View ref_window(ref, rosbag::TopicQuery("/sim/state"), at(0.01), at(0.02));
  EXPECT_EQ(n, ref_window.size());
  EXPECT_GT(n, 50u);
  std::remove(path.c_str());
  std::remove(ref_path.c_str());
}

TEST(BagAppender, LatchedConnectionIsMarkedForPlayback) {
  const std::string path = temp_path("latched");
  {
    BagAppender bag;
    bag.open(path);
    bag.write("/sim/solver_stats", at(1.0), state(1), /*latching=*/true);
    bag.write("/sim/state", at(1.0), state(2));
  }
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::map<std::string, std::string> latching;
  for (const rosbag::ConnectionInfo* c : view.getConnections()) {
    const auto it = c->header->find("latching");
    latching[c->topic] = (it == c->header->end()) ? "" : it->second;
  }
  EXPECT_EQ(latching["/sim/solver_stats"], "1");
  EXPECT_EQ(latching["/sim/state"], "");
  std::remove(path.c_str());
}

TEST(BagAppender, FlushPutsCompleteChunksOnDiskBeforeClose) {
  const std::string path = temp_path("flush");
  BagAppender bag;
  bag.open(path);
  auto file_size = [&] {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    std::fseek(f, 0, SEEK_END);
    const long n = std::ftell(f);
    std::fclose(f);
    return n;
  };
  const long empty = file_size();
  EXPECT_EQ(empty, 13 + 4 + 69 + 4 + (4096 - 69));  // version line + padded file header
  bag.write("/sim/state", at(0.5), state(7));
  bag.flush();
  const long flushed = file_size();
  EXPECT_GT(flushed, empty);  // the chunk is in the file although the bag is open
  bag.close();
  EXPECT_GT(file_size(), flushed);  // the index follows on close
  rosbag::Bag read(path, rosbag::bagmode::Read);
  EXPECT_EQ(rosbag::View(read).size(), 1u);
  std::remove(path.c_str());
}

TEST(BagAppender, RejectsTimesBeforeTimeMinAndUnwritablePaths) {
  BagAppender bag;
  EXPECT_THROW(bag.open("/nonexistent-dir/x.bag"), std::runtime_error);
  const std::string path = temp_path("timemin");
  bag.open(path);
  EXPECT_THROW(bag.write("/sim/state", ros::Time(0, 0), state(0)), std::runtime_error);
  bag.close();
  std::remove(path.c_str());
}
