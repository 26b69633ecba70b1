// Datagrams the kernel dropped on this process's own UDP sockets because
// their receive buffer was full (the "drops" column of /proc/net/udp for the
// socket inodes in /proc/self/fd). LCM reads its socket inside its own
// thread and says nothing when the buffer overflows; this is how a stalled
// process learns what it missed. File reads: for status threads, never for a loop.
#pragma once

#include <dirent.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <set>
#include <string>

namespace igms {

inline int64_t ownUdpDrops() {
  std::set<unsigned long> inodes;
  if (DIR* d = opendir("/proc/self/fd")) {
    while (dirent* e = readdir(d)) {
      char target[64];
      const std::string path = std::string("/proc/self/fd/") + e->d_name;
      const ssize_t n = readlink(path.c_str(), target, sizeof target - 1);
      if (n <= 0) continue;
      target[n] = '\0';
      unsigned long inode = 0;
      if (std::sscanf(target, "socket:[%lu]", &inode) == 1) inodes.insert(inode);
    }
    closedir(d);
  }
  int64_t drops = 0;
  for (const char* table : {"/proc/net/udp", "/proc/net/udp6"}) {
    FILE* f = std::fopen(table, "r");
    if (!f) continue;
    char line[512];
    if (!std::fgets(line, sizeof line, f)) {  // the header
      std::fclose(f);
      continue;
    }
    while (std::fgets(line, sizeof line, f)) {
      unsigned long inode = 0;
      long long drop = 0;
      // sl local rem st tx:rx tr:when retrnsmt uid timeout inode ref pointer drops
      if (std::sscanf(line, "%*s %*s %*s %*s %*s %*s %*s %*s %*s %lu %*s %*s %lld", &inode, &drop) == 2 &&
          inodes.count(inode))
        drops += drop;
    }
    std::fclose(f);
  }
  return drops;
}

}  // namespace igms
