#include "port/q3formats/common/tokenizer.h"

namespace q3 {

Tokenizer::Tokenizer(std::string_view text, std::string file)
    : Tokenizer(text, std::move(file), Options{}) {}

Tokenizer::Tokenizer(std::string_view text, std::string file, Options options)
    : text_(text), file_(std::move(file)), options_(options) {}

bool Tokenizer::skipSpace(bool stopAtNewline) {
  while (pos_ < text_.size()) {
    const unsigned char c = static_cast<unsigned char>(text_[pos_]);
    if (c == '\n') {
      if (stopAtNewline) return true;
      ++line_;
      ++pos_;
    } else if (c <= ' ') {
      ++pos_;
    } else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/') {
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    } else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '*') {
      pos_ += 2;
      while (pos_ < text_.size() && !(text_[pos_] == '*' && pos_ + 1 < text_.size() &&
                                      text_[pos_ + 1] == '/')) {
        if (text_[pos_] == '\n') ++line_;
        ++pos_;
      }
      pos_ = pos_ < text_.size() ? pos_ + 2 : pos_;
    } else if (options_.commaSeparates && c == ',') {
      ++pos_;
    } else {
      return false;
    }
  }
  return false;
}

Token Tokenizer::readToken() {
  Token token;
  token.line = line_;
  auto append = [&](char c) {
    if (token.text.size() < options_.maxTokenLength) token.text.push_back(c);
  };
  if (text_[pos_] == '"') {
    token.quoted = true;
    ++pos_;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      if (text_[pos_] == '\n') ++line_;
      append(text_[pos_++]);
    }
    if (pos_ < text_.size()) ++pos_;  // closing quote (an unterminated string ends at EOF)
    return token;
  }
  while (pos_ < text_.size()) {
    const unsigned char c = static_cast<unsigned char>(text_[pos_]);
    if (c <= ' ' || (options_.commaSeparates && c == ',')) break;
    append(static_cast<char>(c));
    ++pos_;
  }
  return token;
}

std::optional<Token> Tokenizer::next() {
  skipSpace(false);
  if (pos_ >= text_.size()) return std::nullopt;
  return readToken();
}

std::optional<Token> Tokenizer::nextOnLine() {
  if (skipSpace(true) || pos_ >= text_.size()) return std::nullopt;
  return readToken();
}

std::optional<Token> Tokenizer::peek() {
  const Mark saved = mark();
  auto token = next();
  reset(saved);
  return token;
}

void Tokenizer::skipRestOfLine() {
  while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  if (pos_ < text_.size()) {
    ++pos_;
    ++line_;
  }
}

bool Tokenizer::skipBracedSection() {
  int depth = 1;
  while (auto token = next()) {
    if (token->quoted) continue;
    if (token->text == "{") ++depth;
    else if (token->text == "}" && --depth == 0) return true;
  }
  return false;
}

bool Tokenizer::atEnd() {
  skipSpace(false);
  return pos_ >= text_.size();
}

std::string toLowerAscii(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
    if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
    if (x != y) return false;
  }
  return true;
}

int comparePathsLikeEngine(std::string_view a, std::string_view b) {
  auto fold = [](unsigned char c) -> int {
    if (c >= 'a' && c <= 'z') return c - 'a' + 'A';
    if (c == '\\' || c == ':') return '/';
    return c;
  };
  const size_t n = a.size() < b.size() ? a.size() : b.size();
  for (size_t i = 0; i < n; ++i) {
    const int x = fold(static_cast<unsigned char>(a[i])), y = fold(static_cast<unsigned char>(b[i]));
    if (x != y) return x < y ? -1 : 1;
  }
  return a.size() == b.size() ? 0 : (a.size() < b.size() ? -1 : 1);
}

}  // namespace q3
