/* SPDX-License-Identifier: MIT */
/*
** cancel.c -- the clock and cancellation by SIGINT, SIGTERM and SIGHUP
** (cli.h).
*/
#include "common/cli.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static volatile sig_atomic_t got_signal;
static const int cancel_signals[] = {SIGINT, SIGTERM, SIGHUP};
#define NCANCEL (int)(sizeof cancel_signals / sizeof cancel_signals[0])

static void on_signal(int signo)
{
    got_signal = signo;
}

void cli_cancel_begin(void)
{
    int i;
    for (i = 0; i < NCANCEL; i++) {
        struct sigaction sa, old;
        /* A signal ignored at start (nohup, a background job of a
           non-interactive shell) stays ignored. */
        if (sigaction(cancel_signals[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN) continue;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sigemptyset(&sa.sa_mask);
        sigaction(cancel_signals[i], &sa, NULL);
    }
}

int cli_cancelled(void)
{
    return (int)got_signal;
}

static void mask(int how)
{
    sigset_t set;
    int i;
    sigemptyset(&set);
    for (i = 0; i < NCANCEL; i++) sigaddset(&set, cancel_signals[i]);
    sigprocmask(how, &set, NULL);
}

void cli_cancel_hold(void)
{
    mask(SIG_BLOCK);
}
void cli_cancel_release(void)
{
    mask(SIG_UNBLOCK);
}

void cli_cancel_exit(int signo)
{
    signal(signo, SIG_DFL);
    cli_cancel_release();
    raise(signo);
    exit(128 + signo); /* not reached unless the signal is blocked elsewhere */
}
