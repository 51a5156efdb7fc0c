/* SPDX-License-Identifier: MIT */
/*
** version.c -- the smallest program against an installed libggrt:
**   cc version.c $(pkg-config --cflags --libs ggrt) && ./a.out
*/
#include <ggrt.h>

#include <stdio.h>
#include <string.h>

int main(void)
{
    printf("linked against ggrt %s (header %s)\n", ggVersion(), GG_VERSION_STRING);
    return strcmp(ggVersion(), GG_VERSION_STRING) == 0 ? 0 : 1;
}
