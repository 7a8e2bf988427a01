/* The processor-in-the-loop framing, both ends (the board and `neurov pil`,
 * python/neurov/pil/framing.py): one frame is
 *
 *   0xA5 0x5A | type (1 byte) | length (2 bytes) | payload (length bytes) | CRC (2 bytes)
 *
 * little-endian, payload floats IEEE-754 single, CRC-16/CCITT-FALSE
 * (polynomial 0x1021, initial 0xFFFF) over type, length and payload. A
 * receiver resynchronises on the next 0xA5 0x5A after anything it refuses. */
#ifndef NEUROV_PIL_FRAME_H
#define NEUROV_PIL_FRAME_H

#include <stdint.h>

#define PIL_SYNC0 0xA5u
#define PIL_SYNC1 0x5Au
#define PIL_MAX_PAYLOAD 8192u

/* Frame types: host -> board. */
#define PIL_CONFIG 'C'      /* the controller's and allocator's parameters */
#define PIL_MEASUREMENT 'M' /* one period's measurement and desired state */
#define PIL_STATS 'S'       /* asks for the board's counters and stack mark */
/* Frame types: board -> host. */
#define PIL_HELLO 'H'   /* after boot: CPU, FPU, tick rate, N */
#define PIL_ACK 'A'     /* the configuration's status */
#define PIL_COMMAND 'T' /* the answer to a measurement (or a fault) */
#define PIL_REPORT 'R'  /* the answer to PIL_STATS */

/* Why the board answered with its safe command (PIL_COMMAND's fault byte). */
#define PIL_FAULT_NONE 0u
#define PIL_FAULT_BAD_FRAME 1u    /* CRC, length or type wrong: the frame was dropped */
#define PIL_FAULT_OUT_OF_RANGE 2u /* a finite measurement outside the configured limits */
#define PIL_FAULT_TIMEOUT 3u      /* no measurement for the watchdog period */
#define PIL_FAULT_NOT_CONFIGURED 4u /* a measurement before a valid configuration */

uint16_t pil_crc16(uint16_t crc, const uint8_t* data, uint32_t length);

/* A receiver fed byte by byte. */
typedef struct pil_parser {
  uint32_t state, length, got;
  uint8_t type;
  uint16_t crc;
  uint8_t payload[PIL_MAX_PAYLOAD + 2];
} pil_parser;

typedef enum pil_parse_result { PIL_MORE = 0, PIL_FRAME = 1, PIL_BAD = 2 } pil_parse_result;

void pil_parser_reset(pil_parser* p);
/* PIL_FRAME: a whole frame with a good CRC is in p->type / p->payload /
 * p->length; PIL_BAD: a frame was refused (the parser is ready again). */
pil_parse_result pil_parser_feed(pil_parser* p, uint8_t byte);

/* Writes one frame through the board's UART. */
void pil_send(uint8_t type, const uint8_t* payload, uint32_t length);

#endif
