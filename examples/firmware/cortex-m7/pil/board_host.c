/* The processor-in-the-loop task as a host program (`neurov pil` builds it
 * with the host's compiler to run the same float controller beside the
 * board): the link is stdin/stdout, the ticks are microseconds, there is no
 * stack painting (board_stack_used() is 0). */
#define _POSIX_C_SOURCE 200809L
#include <poll.h>
#include <time.h>
#include <unistd.h>

#include "board.h"

static unsigned char in[4096];
static ssize_t in_len, in_at;

void board_init(void) {}

uint32_t board_tick_hz(void) { return 1000000u; }

uint32_t board_ticks(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (uint32_t)((uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u);
}

int board_read(uint32_t since, uint32_t timeout) {
  while (in_at >= in_len) {
    int wait = -1;
    if (timeout != 0u) {
      const uint32_t spent = board_ticks() - since;
      if (spent >= timeout) return -1;
      wait = (int)((timeout - spent + 999u) / 1000u);
    }
    struct pollfd p = {0, POLLIN, 0};
    if (poll(&p, 1, wait) <= 0) continue;
    in_len = read(0, in, sizeof in);
    in_at = 0;
    if (in_len <= 0) _exit(0); /* the host closed the link */
  }
  return in[in_at++];
}

void board_write(const uint8_t* data, uint32_t length) {
  while (length > 0) {
    const ssize_t n = write(1, data, length);
    if (n <= 0) _exit(0);
    data += n;
    length -= (uint32_t)n;
  }
}

uint32_t board_cpuid(void) { return 0u; }
uint32_t board_mvfr0(void) { return 0u; }
uint32_t board_stack_used(void) { return 0u; }
uint32_t board_stack_size(void) { return 0u; }
