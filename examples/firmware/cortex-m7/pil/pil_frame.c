/* The framing of pil_frame.h: CRC, the byte-wise receiver and the sender. */
#include "pil_frame.h"

#include "board.h"

uint16_t pil_crc16(uint16_t crc, const uint8_t* data, uint32_t length) {
  for (uint32_t i = 0; i < length; ++i) {
    crc ^= (uint16_t)((uint16_t)data[i] << 8);
    for (int b = 0; b < 8; ++b) crc = (crc & 0x8000u) ? (uint16_t)((crc << 1) ^ 0x1021u) : (uint16_t)(crc << 1);
  }
  return crc;
}

enum { WAIT_SYNC0, WAIT_SYNC1, TYPE, LEN0, LEN1, PAYLOAD };

void pil_parser_reset(pil_parser* p) {
  p->state = WAIT_SYNC0;
  p->length = p->got = 0;
}

pil_parse_result pil_parser_feed(pil_parser* p, uint8_t byte) {
  switch (p->state) {
    case WAIT_SYNC0:
      if (byte == PIL_SYNC0) p->state = WAIT_SYNC1;
      return PIL_MORE;
    case WAIT_SYNC1:
      p->state = byte == PIL_SYNC1 ? TYPE : (byte == PIL_SYNC0 ? WAIT_SYNC1 : WAIT_SYNC0);
      return PIL_MORE;
    case TYPE:
      p->type = byte;
      p->state = LEN0;
      return PIL_MORE;
    case LEN0:
      p->length = byte;
      p->state = LEN1;
      return PIL_MORE;
    case LEN1:
      p->length |= (uint32_t)byte << 8;
      if (p->length > PIL_MAX_PAYLOAD) {
        pil_parser_reset(p);
        return PIL_BAD;
      }
      p->got = 0;
      p->state = PAYLOAD;
      return PIL_MORE;
    default: {
      p->payload[p->got++] = byte;
      if (p->got < p->length + 2u) return PIL_MORE;
      const uint8_t head[3] = {p->type, (uint8_t)(p->length & 0xFFu), (uint8_t)(p->length >> 8)};
      uint16_t crc = pil_crc16(0xFFFFu, head, 3);
      crc = pil_crc16(crc, p->payload, p->length);
      const uint16_t sent = (uint16_t)(p->payload[p->length] | (p->payload[p->length + 1] << 8));
      p->state = WAIT_SYNC0;
      return crc == sent ? PIL_FRAME : PIL_BAD;
    }
  }
}

void pil_send(uint8_t type, const uint8_t* payload, uint32_t length) {
  const uint8_t head[5] = {PIL_SYNC0, PIL_SYNC1, type, (uint8_t)(length & 0xFFu), (uint8_t)(length >> 8)};
  uint16_t crc = pil_crc16(0xFFFFu, head + 2, 3);
  crc = pil_crc16(crc, payload, length);
  const uint8_t tail[2] = {(uint8_t)(crc & 0xFFu), (uint8_t)(crc >> 8)};
  board_write(head, 5);
  board_write(payload, length);
  board_write(tail, 2);
}
