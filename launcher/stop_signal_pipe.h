// InstallStopSignalPipe: SIGINT and SIGTERM turned into a readable pipe for a poll loop.
#pragma once

namespace dt {

// Makes SIGINT and SIGTERM write one byte to a pipe and ignores SIGPIPE (a child that dies
// mid-write must not kill the supervisor). Returns the pipe's read end, non-blocking and
// close-on-exec, for the supervisor to poll beside its children; -1 if no pipe can be made.
// Call once per process.
int InstallStopSignalPipe();

}  // namespace dt
