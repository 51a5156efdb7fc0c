/* SPDX-License-Identifier: MIT */
/*
** reader_none.c -- libggrt-core's default image reader: none. libggrt
** links imageio/reader.c instead (see load.h).
*/
#include "load.h"

ggImageReader gg_load_default_reader(void) { return NULL; }
