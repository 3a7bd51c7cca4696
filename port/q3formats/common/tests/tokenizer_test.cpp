#include "port/q3formats/common/tokenizer.h"

#include <gtest/gtest.h>

namespace {

TEST(Tokenizer, SplitsOnWhitespaceAndSkipsComments) {
  q3::Tokenizer t("a b // comment\n/* block\n comment */ c\t\"quoted string\" d", "t.txt");
  auto a = t.next();
  ASSERT_TRUE(a);
  EXPECT_EQ(a->text, "a");
  EXPECT_EQ(a->line, 1);
  EXPECT_EQ(t.next()->text, "b");
  auto c = t.next();
  EXPECT_EQ(c->text, "c");
  EXPECT_EQ(c->line, 3);
  auto q = t.next();
  EXPECT_EQ(q->text, "quoted string");
  EXPECT_TRUE(q->quoted);
  EXPECT_EQ(t.next()->text, "d");
  EXPECT_FALSE(t.next());
  EXPECT_TRUE(t.atEnd());
}

TEST(Tokenizer, NextOnLineStopsAtLineBreakAndKeepsCursor) {
  q3::Tokenizer t("map x.tga\r\nblendFunc add\n", "t.txt");
  EXPECT_EQ(t.next()->text, "map");
  EXPECT_EQ(t.nextOnLine()->text, "x.tga");
  EXPECT_FALSE(t.nextOnLine());
  EXPECT_FALSE(t.nextOnLine());
  auto b = t.next();
  EXPECT_EQ(b->text, "blendFunc");
  EXPECT_EQ(b->line, 2);
  EXPECT_EQ(t.nextOnLine()->text, "add");
}

TEST(Tokenizer, CommentEndsTheLine) {
  q3::Tokenizer t("a // b c\nd", "t.txt");
  t.next();
  EXPECT_FALSE(t.nextOnLine());
  EXPECT_EQ(t.next()->text, "d");
}

TEST(Tokenizer, SkipBracedSectionHandlesNesting) {
  q3::Tokenizer t("{ a { b } c } after", "t.txt");
  EXPECT_EQ(t.next()->text, "{");
  EXPECT_TRUE(t.skipBracedSection());
  EXPECT_EQ(t.next()->text, "after");
  q3::Tokenizer open("{ a { b }", "t.txt");
  open.next();
  EXPECT_FALSE(open.skipBracedSection());
}

TEST(Tokenizer, UnterminatedCommentAndStringEndSafely) {
  q3::Tokenizer t("x /* never closed", "t.txt");
  EXPECT_EQ(t.next()->text, "x");
  EXPECT_FALSE(t.next());
  q3::Tokenizer s("\"open", "t.txt");
  EXPECT_EQ(s.next()->text, "open");
  EXPECT_FALSE(s.next());
}

TEST(Tokenizer, CommaSeparatesInSkinMode) {
  q3::Tokenizer t("h_head,models/a.tga\n\"u_torso\" , \"b c.tga\"", "a.skin", {.commaSeparates = true});
  EXPECT_EQ(t.next()->text, "h_head");
  EXPECT_EQ(t.nextOnLine()->text, "models/a.tga");
  EXPECT_EQ(t.next()->text, "u_torso");
  EXPECT_EQ(t.nextOnLine()->text, "b c.tga");
}

TEST(Tokenizer, TruncatesOverlongTokens) {
  std::string longWord(5000, 'x');
  q3::Tokenizer t(longWord, "t.txt");
  EXPECT_EQ(t.next()->text.size(), 1024u);
  EXPECT_FALSE(t.next());
}

TEST(Tokenizer, CaseHelpers) {
  EXPECT_EQ(q3::toLowerAscii("Textures/BASE_Wall"), "textures/base_wall");
  EXPECT_TRUE(q3::equalsIgnoreCase("GL_ONE", "gl_one"));
  EXPECT_FALSE(q3::equalsIgnoreCase("a", "ab"));
}

}  // namespace

namespace {
TEST(Tokenizer, EnginePathOrderFoldsToUpperCase) {
  EXPECT_EQ(q3::comparePathsLikeEngine("pak0.pk3", "PAK0.PK3"), 0);
  EXPECT_LT(q3::comparePathsLikeEngine("pak0.pk3", "pak1.pk3"), 0);
  // Upper-case folding puts '_' (0x5F) after letters, unlike a lower-case compare.
  EXPECT_GT(q3::comparePathsLikeEngine("a_b", "aab"), 0);
  EXPECT_EQ(q3::comparePathsLikeEngine("a\\b", "a/b"), 0);
  EXPECT_LT(q3::comparePathsLikeEngine("pak", "pak0"), 0);
}
}  // namespace
