// The console on its own: lines queued while a command runs, a line run only once its whole answer
// has room in the ring, answers held until the board reports a save.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "dynweigh/firmware/console.hpp"

namespace dynweigh::firmware {
namespace {

void type(Console& console, const std::string& text) { console.receive(text.data(), text.size(), false); }

std::string drained(Console& console) {
  char buffer[TextWriter::kCapacity];
  return std::string(buffer, console.drain(buffer, sizeof buffer));
}

TEST(ConsolePart, LinesBeyondTheQueueAreRefusedBusyAndTheQueuedOnesKeptInOrder) {
  Console console;
  std::string typed;
  for (std::size_t i = 0; i <= Console::kQueue; ++i) typed += "line" + std::to_string(i) + "\r\n";
  type(console, typed);
  EXPECT_EQ(console.queued(), Console::kQueue);
  EXPECT_EQ(drained(console), "ERR 3 busy\n");
  for (std::size_t i = 0; i < Console::kQueue; ++i) {
    Console::Line* line = console.next_line();
    ASSERT_NE(line, nullptr);
    EXPECT_STREQ(line->text, ("line" + std::to_string(i)).c_str());
    console.pop_line();
  }
  EXPECT_EQ(console.next_line(), nullptr);
}

TEST(ConsolePart, ALineWaitsUntilTheRingHasRoomForItsWholeAnswer) {
  Console console;
  const std::string filler(TextWriter::kCapacity - Console::kRoomForAnAnswer + 1, 'x');
  console.write(filler.c_str());
  type(console, "status\n");
  EXPECT_EQ(console.next_line(), nullptr);
  char byte;
  console.drain(&byte, 1);  // the board sends one byte: now there is room
  EXPECT_NE(console.next_line(), nullptr);
}

TEST(ConsolePart, AnAnswerHeldForTheSaveHoldsTheNextLineAndSaysHowTheSaveWent) {
  Console console;
  type(console, "param echo 1\nstatus\n");
  console.pop_line();  // the first ran and changed the settings
  console.hold_ok();
  EXPECT_TRUE(console.answers_held());
  EXPECT_EQ(console.next_line(), nullptr);
  console.release_held_answers(false);
  EXPECT_EQ(drained(console), "OK\n");
  EXPECT_NE(console.next_line(), nullptr);
  console.hold_ok();
  console.release_held_answers(true);
  EXPECT_EQ(drained(console), "ERR 4 fault nvm_error\n");
}

TEST(ConsolePart, ALineTooLongIsQueuedEmptyToBeAnsweredOnce) {
  Console console;
  type(console, std::string(ConsoleLineReader::kMaxLine + 10, 'a') + "\n");
  Console::Line* line = console.next_line();
  ASSERT_NE(line, nullptr);
  EXPECT_TRUE(line->too_long);
  EXPECT_EQ(std::strlen(line->text), 0u);
}

TEST(ConsolePart, EchoWritesWhatATerminalShows) {
  Console console;
  const std::string typed = "ab\x7f" "c\r\n";
  console.receive(typed.data(), typed.size(), true);
  EXPECT_EQ(drained(console), "ab\b \bc\n");
  EXPECT_STREQ(console.next_line()->text, "ac");
}

}  // namespace
}  // namespace dynweigh::firmware
