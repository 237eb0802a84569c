#!/usr/bin/env bash
# Compiles the firmware (firmware/softwrist_fw) for the paper's Arduino Uno (ATmega328P, 16 MHz) with Debian's
# avr-gcc and Arduino AVR core (packages gcc-avr, avr-libc, arduino-core-avr; `scripts/setup.sh --tests` installs
# them), with warnings as errors, and prints its size. Output: build/firmware/softwrist_fw.{elf,hex}.
#   bash scripts/build_firmware.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/firmware}
arduino=/usr/share/arduino/hardware/arduino/avr
for tool in avr-gcc avr-g++ avr-objcopy avr-size; do
  command -v "$tool" >/dev/null || { echo "build_firmware: $tool not found (install gcc-avr binutils-avr avr-libc)" >&2; exit 1; }
done
[ -d "$arduino/cores/arduino" ] || { echo "build_firmware: no Arduino AVR core at $arduino (install arduino-core-avr)" >&2; exit 1; }

mkdir -p "$out"
common=(-mmcu=atmega328p -DF_CPU=16000000L -DARDUINO=10819 -DARDUINO_AVR_UNO -DARDUINO_ARCH_AVR -Os
        -ffunction-sections -fdata-sections
        -I"$arduino/cores/arduino" -I"$arduino/variants/standard" -I"$arduino/libraries/Wire/src")
cflags=("${common[@]}" -std=gnu11)
cxxflags=("${common[@]}" -std=gnu++11 -fno-exceptions -fno-threadsafe-statics)

objects=()
# The Arduino core and the Wire library, as they are, with the flags of its platform.txt (-fpermissive; their
# warnings are not ours).
for source in "$arduino"/cores/arduino/*.c "$arduino"/libraries/Wire/src/utility/twi.c; do
  object="$out/$(basename "$source").o"; avr-gcc "${cflags[@]}" -w -c "$source" -o "$object"; objects+=("$object")
done
for source in "$arduino"/cores/arduino/*.cpp "$arduino"/libraries/Wire/src/Wire.cpp; do
  # DECIMAL_DIG: GCC 5's <float.h> defines it for C99 only; the core's WString.cpp uses it in C++.
  object="$out/$(basename "$source").o"
  avr-g++ "${cxxflags[@]}" -fpermissive -w -DDECIMAL_DIG=__DECIMAL_DIG__ -c "$source" -o "$object"
  objects+=("$object")
done
# Ours, with warnings as errors; it includes the host's protocol and safety headers from src/.
avr-g++ "${cxxflags[@]}" -Wall -Wextra -Werror -Isrc -Ifirmware/softwrist_fw \
  -c firmware/softwrist_fw/softwrist_fw.cpp -o "$out/softwrist_fw.o"
avr-gcc -mmcu=atmega328p -Os -Wl,--gc-sections "$out/softwrist_fw.o" "${objects[@]}" -lm -o "$out/softwrist_fw.elf"
avr-objcopy -O ihex -R .eeprom "$out/softwrist_fw.elf" "$out/softwrist_fw.hex"
avr-size "$out/softwrist_fw.elf"
# The Uno has 32 KiB of flash (0.5 KiB for the bootloader) and 2 KiB of RAM.
avr-size "$out/softwrist_fw.elf" | awk 'NR == 2 {
  flash = $1 + $2; ram = $2 + $3
  printf "firmware: %d bytes of flash (of 32256), %d bytes of static RAM (of 2048)\n", flash, ram
  if (flash > 32256 || ram > 1536) { print "firmware: too large for the Uno" > "/dev/stderr"; exit 1 }
}'
