// The DDS helpers for forgetting departed clients: which writers a reader has matched now
// (a real participant's), and erasing bookkeeping of those no longer matched.
#include "idl/protocol/dds.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "idl/monocle_msgs.h"

namespace monocle::dds {
namespace {

TEST(DdsTest, EraseUnmatchedKeepsMatchedAndKeptEntries) {
  std::map<dds_instance_handle_t, std::string> by_writer{{1, "a"}, {5, "b"}, {9, "c"}, {12, "d"}};
  EraseUnmatched(by_writer, {5, 7, 12}, [](const auto& e) { return e.second == "c"; });
  EXPECT_EQ(by_writer,
            (std::map<dds_instance_handle_t, std::string>{{5, "b"}, {9, "c"}, {12, "d"}}));

  std::set<dds_instance_handle_t> seen{2, 3, 4};
  EraseUnmatched(seen, {3}, [](dds_instance_handle_t) { return false; });
  EXPECT_EQ(seen, (std::set<dds_instance_handle_t>{3}));
  EraseUnmatched(seen, {}, [](dds_instance_handle_t) { return false; });
  EXPECT_TRUE(seen.empty());
}

// More writers than MatchedPublications first asks room for (64): all of them, sorted, and
// none once they are gone.
TEST(DdsTest, MatchedPublicationsListsEveryMatchedWriter) {
  const dds_entity_t participant = dds_create_participant(61, nullptr, nullptr);
  ASSERT_GT(participant, 0);
  const dds_entity_t topic = dds_create_topic(
      participant, &monocle_msgs_msg_dds__CameraStatus__desc, "dds_test_status", nullptr, nullptr);
  ASSERT_GT(topic, 0);
  const dds_entity_t reader = dds_create_reader(participant, topic, nullptr, nullptr);
  ASSERT_GT(reader, 0);
  std::vector<dds_entity_t> writers;
  std::vector<dds_instance_handle_t> handles;
  for (int i = 0; i < 70; ++i) {
    writers.push_back(dds_create_writer(participant, topic, nullptr, nullptr));
    ASSERT_GT(writers.back(), 0);
    dds_instance_handle_t h = 0;
    ASSERT_EQ(dds_get_instance_handle(writers.back(), &h), DDS_RETCODE_OK);
    handles.push_back(h);
  }
  std::sort(handles.begin(), handles.end());
  const auto matched = MatchedPublications(reader);
  ASSERT_TRUE(matched.has_value());
  EXPECT_EQ(*matched, handles);

  for (const dds_entity_t w : writers) ASSERT_EQ(dds_delete(w), DDS_RETCODE_OK);
  const auto after = MatchedPublications(reader);
  ASSERT_TRUE(after.has_value());
  EXPECT_TRUE(after->empty());
  EXPECT_FALSE(MatchedPublications(topic).has_value());  // not a reader: cannot say
  dds_delete(participant);
}

}  // namespace
}  // namespace monocle::dds
