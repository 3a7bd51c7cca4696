#pragma once
// The one Quake-style text tokenizer of the formats library (shader scripts, skins, entities).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace q3 {

/// One token of a Quake text file.
struct Token {
  std::string text;     ///< the token, without quotes
  int line = 0;         ///< 1-based line where the token starts
  bool quoted = false;  ///< true if it was written as "a quoted string"
};

/// Splits Quake text into tokens the way the engine's parser does: whitespace separates tokens,
/// `//` and `/* */` comments are skipped, "quoted strings" are one token (no escapes), and the
/// caller chooses whether the next token may be on a later line. Never reads out of bounds.
class Tokenizer {
 public:
  /// Options that differ between Quake file kinds.
  struct Options {
    bool commaSeparates = false;  ///< skins: ',' ends a token and is dropped (engine's CommaParse)
    size_t maxTokenLength = 1024; ///< longer tokens are truncated (the engine's MAX_TOKEN_CHARS)
  };

  /// Tokenizes `text`; `file` names it in messages. The text must outlive the tokenizer.
  Tokenizer(std::string_view text, std::string file);
  Tokenizer(std::string_view text, std::string file, Options options);

  /// Next token anywhere after the cursor; nullopt at end of text.
  std::optional<Token> next();
  /// Next token only if it starts on the current line; nullopt (cursor kept) otherwise.
  std::optional<Token> nextOnLine();
  /// Next token without consuming it (line breaks allowed).
  std::optional<Token> peek();
  /// Skips everything up to and including the end of the current line.
  void skipRestOfLine();
  /// After an opening `{` was read: skips to its matching `}` (nesting-aware).
  /// Returns false if the text ends first.
  bool skipBracedSection();

  /// A saved cursor position (see mark/reset).
  struct Mark {
    size_t pos = 0;
    int line = 1;
  };
  /// Current cursor, to return to with reset().
  Mark mark() const { return {pos_, line_}; }
  /// Moves the cursor back to a saved mark.
  void reset(Mark m) {
    pos_ = m.pos;
    line_ = m.line;
  }

  /// True when only whitespace and comments remain.
  bool atEnd();
  /// Line of the cursor (1-based).
  int line() const { return line_; }
  /// Name used in messages.
  const std::string& file() const { return file_; }

 private:
  /// Skips whitespace and comments; stops before a newline if `stopAtNewline`.
  /// Returns true if it stopped because of a newline.
  bool skipSpace(bool stopAtNewline);
  Token readToken();

  std::string_view text_;
  std::string file_;
  Options options_;
  size_t pos_ = 0;
  int line_ = 1;
};

/// ASCII lower-case copy (Quake names are compared case-insensitively).
std::string toLowerAscii(std::string_view s);
/// Case-insensitive ASCII equality.
bool equalsIgnoreCase(std::string_view a, std::string_view b);

/// The engine's path order (FS_PathCmp): ASCII letters folded to upper case, '\\' and ':' read as
/// '/'. Negative, zero or positive like strcmp. Used to sort pk3 archives and shader scripts.
int comparePathsLikeEngine(std::string_view a, std::string_view b);

}  // namespace q3
