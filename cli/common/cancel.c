/* SPDX-License-Identifier: MIT */
/*
** cancel.c -- the clock, cancellation by SIGINT, SIGTERM and SIGHUP,
** and the progress bar that checks for it (cli.h).
*/
#include "common/cli.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

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

void cli_cancel_after_write(const char *path)
{
    sigset_t pending;
    int i;
    if (sigpending(&pending) != 0) return;
    for (i = 0; i < NCANCEL; i++)
        if (sigismember(&pending, cancel_signals[i]) == 1) {
            cli_error("signal %d came while %s was being written: it is written whole; "
                      "stopping",
                      cancel_signals[i], path);
            return;
        }
}

double cli_bar_delay(double dflt)
{
    static int looked;
    static double delay = -1;
    if (!looked) {
        const char *v = getenv("GGRT_PROGRESS_DELAY");
        char why[96];
        looked = 1;
        if (v && cli_parse_num(v, 0, 1e9, &delay, why, sizeof why) != 0) {
            cli_warn("GGRT_PROGRESS_DELAY=%s: %s (seconds, 0 or more); ignored", v, why);
            delay = -1;
        }
    }
    return delay >= 0 ? delay : dflt;
}

void cli_bar_begin(cli_bar *b, const char *label, int quiet)
{
    b->label = label ? label : "", b->t0 = cli_now(), b->last_pct = -1;
    b->after = cli_bar_delay(0);
    b->draw = !quiet && isatty(2);
}

int cli_bar_step(void *ud, long done, long total)
{
    cli_bar *b = ud;
    int pct = total > 0 ? (int)(100.0 * (double)done / (double)total) : 100, i;
    double el;
    if (cli_cancelled()) return 1;
    if (!b || !b->draw || pct == b->last_pct) return 0;
    if ((el = cli_now() - b->t0) < b->after) return 0;
    b->last_pct = pct;
    fprintf(stderr, "\r%s%s[", b->label, *b->label ? " " : "");
    for (i = 0; i < 40; i++) fputc(i < pct * 40 / 100 ? '#' : '.', stderr);
    fprintf(stderr, "] %3d%%  %.1fs", pct, el);
    if (pct > 0 && pct < 100)
        fprintf(stderr, "  ~%.0fs left ", el * (100 - pct) / pct);
    else
        fprintf(stderr, "             ");
    fflush(stderr);
    return 0;
}

void cli_bar_end(cli_bar *b)
{
    if (b->draw && b->last_pct >= 0) fputc('\n', stderr);
    b->last_pct = -1;
}
