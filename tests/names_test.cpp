// Names at the edge: UTF-8 validity by RFC 3629's table, control characters, and the linear-time
// unique-name maker of the BVH and pivot-rig code; CSV quoting of names.
#include "physik/model/names.h"

#include <gtest/gtest.h>

#include "physik/io/pose_io.h"
#include "physik/model/unique_names.h"

namespace physik {
namespace {

TEST(Names, Utf8ByRfc3629) {
  EXPECT_TRUE(valid_utf8(""));
  EXPECT_TRUE(valid_utf8("hand.L"));
  EXPECT_TRUE(valid_utf8("caf\xc3\xa9"));        // U+00E9
  EXPECT_TRUE(valid_utf8("\xe2\x98\x83"));       // U+2603
  EXPECT_TRUE(valid_utf8("\xf0\x9f\x98\x80"));   // U+1F600
  EXPECT_TRUE(valid_utf8("\xf4\x8f\xbf\xbf"));   // U+10FFFF, the last
  EXPECT_FALSE(valid_utf8("\xff"));              // never in UTF-8
  EXPECT_FALSE(valid_utf8("\xc3"));              // truncated
  EXPECT_FALSE(valid_utf8("\xc0\xaf"));          // overlong '/'
  EXPECT_FALSE(valid_utf8("\xe0\x80\xaf"));      // overlong, 3 bytes
  EXPECT_FALSE(valid_utf8("\xed\xa0\x80"));      // a surrogate, U+D800
  EXPECT_FALSE(valid_utf8("\xf4\x90\x80\x80"));  // U+110000, past the last
  EXPECT_FALSE(valid_utf8("\x80"));              // a lone continuation byte
  EXPECT_FALSE(valid_utf8("ab\xe2\x82"));        // truncated at the end
}

TEST(Names, ProblemsSayWhichByteAndWhere) {
  EXPECT_EQ(name_problem("forearm.L"), "");
  EXPECT_EQ(name_problem("a\"b<c>&,d"), "");  // reserved by formats, escaped by their writers
  EXPECT_EQ(name_problem("ab\xff"), "byte 0xff at offset 2 is not UTF-8");
  EXPECT_EQ(name_problem("a\tb"), "control character 0x09 at offset 1");
  EXPECT_EQ(name_problem("a\x7f"), "control character 0x7f at offset 1");
}

TEST(UniqueNames, FirstFreeSuffixInLinearTime) {
  UniqueNames u;
  EXPECT_EQ(u.make("a"), "a");
  EXPECT_EQ(u.make("a"), "a_2");
  EXPECT_TRUE(u.take("a_3"));  // taken from outside: skipped
  EXPECT_EQ(u.make("a"), "a_4");
  EXPECT_EQ(u.make("a_2"), "a_2_2");
  EXPECT_FALSE(u.take("a_4"));
  // 100,000 equal names: each costs O(1) (the quadratic version took minutes)
  UniqueNames many;
  std::string last;
  for (int i = 0; i < 100000; ++i) last = many.make("s");
  EXPECT_EQ(last, "s_100000");
}

TEST(CsvField, QuotesOnlyWhatNeedsIt) {
  EXPECT_EQ(csv_field("hand.L"), "hand.L");
  EXPECT_EQ(csv_field("a<b"), "a<b");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("a\"b"), "\"a\"\"b\"");
}

}  // namespace
}  // namespace physik
