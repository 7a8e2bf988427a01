#!/usr/bin/env bash
# Instructions per control step of neurov_c's float code for a Cortex-M7
# (-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -Os, newlib's libm), for
# several N, counted under qemu-arm (Debian: qemu-user). docs/firmware.md
# turns the counts into a time at 216 MHz. Usage, from the repository:
#
#   [OPT=-O2] bash examples/firmware/cortex-m7/instruction_count.sh [N ...]   (default 16 64 256)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# OPT=-O2 shows what optimising for speed rather than size buys.
flags=(-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb "${OPT:--Os}" -DNDEBUG
       -ffunction-sections -fdata-sections -I"$root/cpp/include" -isystem /usr/include/eigen3)
steps=20

# qemu's M-profile CPUs do not run in user mode; "max" (ARMv8-A, AArch32)
# executes the same Thumb-2 and FPv5 instructions, so the count is the same.
count() {  # binary -> instructions executed
  qemu-arm -cpu max -singlestep -d exec,nochain "$1" 2>&1 >/dev/null | grep -c '^Trace' || true
}

printf '%6s %14s %14s %14s %14s\n' N "reference step" "NN step" "allocation" "estimator"
sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(16 64 256)
for n in "${sizes[@]}"; do
  objects=()
  for src in c_api c_api_allocation c_api_estimator; do
    arm-none-eabi-g++ "${flags[@]}" -fno-exceptions -fno-rtti -DNEUROV_C_CENTRES="$n" \
      -c "$root/cpp/src/$src.cpp" -o "$work/${src}_$n.o"
    objects+=("$work/${src}_$n.o")
  done
  counts=()
  for loop in 0 1 2 3 4; do
    arm-none-eabi-gcc "${flags[@]}" -std=c11 -DNEUROV_C_CENTRES="$n" -DLOOP=$loop \
      -DSTEPS=$steps -nostartfiles -static -Wl,--gc-sections -Wl,-Ttext=0x10000 \
      --specs=nano.specs "$here/instruction_count.c" "${objects[@]}" -lm \
      -o "$work/count_${n}_$loop.elf"
    counts[$loop]=$(count "$work/count_${n}_$loop.elf")
  done
  printf '%6d %14d %14d %14d %14d\n' "$n" $(( (counts[1] - counts[0]) / steps )) \
    $(( (counts[2] - counts[1]) / steps )) $(( (counts[3] - counts[2]) / steps )) \
    $(( (counts[4] - counts[3]) / steps ))
done
