#pragma once
// The journal of a grid: one line per finished job, appended and flushed as each row arrives, so
// that a run that dies (a rank, the writer, the node) loses only the jobs in progress.
//
//   # dynweigh grid journal v1: <signature>
//   <key> TAB <row> TAB <checksum>
//
// The signature names what else decides a row (e.g. `bench seeds=50`); a resume refuses a journal
// of another signature. The checksum (FNV-1a, 64 bits, hex) covers key and row: a line cut short by
// a crash, or garbage a crashed file system left, is dropped and its job computed again.
#include <cstdio>
#include <map>
#include <string>

namespace dynweigh::tools::grid {

struct JournalContents {
  std::map<std::string, std::string> rows;  // key -> row, intact lines only (the first of a key wins)
  std::size_t dropped_lines = 0;            // cut short or corrupt
};

// The intact rows of the journal at `path`; empty when there is none yet (or not even a whole
// header). Throws when the journal was written for another signature.
JournalContents read_journal(const std::string& path, const std::string& signature);

// The key and row of one journal line, or false when the line is not intact.
bool parse_journal_line(const std::string& line, std::string& key, std::string& row);
std::string journal_line(const std::string& key, const std::string& row);

class JournalWriter {
 public:
  // Starts the journal afresh with the rows of `kept` (a resume's intact rows; written to a
  // temporary file renamed over the old one, so a crash now loses nothing either).
  JournalWriter(const std::string& path, const std::string& signature, const JournalContents& kept);
  ~JournalWriter();
  JournalWriter(const JournalWriter&) = delete;
  JournalWriter& operator=(const JournalWriter&) = delete;

  // One line, flushed before returning.
  void append(const std::string& key, const std::string& row);

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
};

// Keys and rows go on one line between tabs: neither may hold a tab or a line break.
void check_journal_field(const std::string& what, const std::string& text);

}  // namespace dynweigh::tools::grid
