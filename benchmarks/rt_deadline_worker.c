/* A cyclicdeadline-like periodic job for benchmarks/rt_deadline_experiment.py (the thesis ran rt-tests'
 * cyclicdeadline in each container). It does not set its own policy: continuum.agent makes it a SCHED_DEADLINE
 * task before exec; it only does the work of each job and measures whether the job met its deadline.
 *
 *   rt_deadline_worker job WCET_US PERIOD_US DEADLINE_US SECONDS SEED GO [HIGH]   one periodic task
 *   rt_deadline_worker stress MIB SECONDS GO                               memory stress (SCHED_OTHER)
 *
 * Both wait (polling every 10 ms) until the file GO exists, so that a set of them starts together once every
 * one has been admitted (or refused) by the kernel, in creation order.
 *
 * job: each job burns U(0.3, HIGH) x WCET of its own CPU time (HIGH default 1.0) (CLOCK_THREAD_CPUTIME_ID), then sched_yield()s,
 * which under SCHED_DEADLINE gives up the rest of the runtime until the next period. Job k is released at
 * t0 + k*PERIOD (t0: the start of a period, after a first yield) and misses if it completes after its release
 * + DEADLINE. A job that completes after the next release starts the next one at once (backlog), as a real
 * periodic task would. Prints {"jobs": n, "missed": m, "max_lateness_us": x} on stdout.
 */
#define _GNU_SOURCE
#include <sched.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static void wait_for(const char *go) {
    while (access(go, F_OK) != 0) usleep(10000);
}

static int64_t now_ns(clockid_t clock) {
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static uint64_t rng_state;
static double uniform(void) { /* xorshift64*: a fixed sequence per seed */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (double)((rng_state * 2685821657736338717ULL) >> 11) / 9007199254740992.0;
}

static int job(int argc, char **argv) {
    if (argc != 8 && argc != 9) return 2;
    double high = argc == 9 ? atof(argv[8]) : 1.0;
    wait_for(argv[7]);
    int64_t wcet = atoll(argv[2]) * 1000, period = atoll(argv[3]) * 1000, deadline = atoll(argv[4]) * 1000;
    int64_t seconds = atoll(argv[5]);
    rng_state = (uint64_t)atoll(argv[6]) * 0x9E3779B97F4A7C15ULL + 1;
    sched_yield(); /* start at a period's beginning */
    int64_t t0 = now_ns(CLOCK_MONOTONIC), end = t0 + seconds * 1000000000LL;
    long jobs = 0, missed = 0;
    int64_t max_late = 0;
    for (long k = 0;; k++) {
        int64_t release = t0 + k * period;
        if (release >= end) break;
        int64_t demand = (int64_t)((0.3 + (high - 0.3) * uniform()) * (double)wcet);
        int64_t start = now_ns(CLOCK_THREAD_CPUTIME_ID);
        while (now_ns(CLOCK_THREAD_CPUTIME_ID) - start < demand) {
        }
        int64_t done = now_ns(CLOCK_MONOTONIC), late = done - (release + deadline);
        jobs++;
        if (late > 0) {
            missed++;
            if (late > max_late) max_late = late;
        }
        if (done < release + period) sched_yield(); /* wait for the next period */
    }
    printf("{\"jobs\": %ld, \"missed\": %ld, \"max_lateness_us\": %lld}\n", jobs, missed, (long long)(max_late / 1000));
    return 0;
}

static int stress(int argc, char **argv) {
    if (argc != 5) return 2;
    wait_for(argv[4]);
    size_t size = (size_t)atoll(argv[2]) << 20;
    int64_t end = now_ns(CLOCK_MONOTONIC) + atoll(argv[3]) * 1000000000LL;
    volatile unsigned char *buf = malloc(size);
    if (!buf) return 1;
    unsigned long passes = 0;
    while (now_ns(CLOCK_MONOTONIC) < end) {
        for (size_t i = 0; i < size; i += 64) buf[i] += 1; /* one write per cache line */
        passes++;
    }
    printf("{\"passes\": %lu}\n", passes);
    return 0;
}

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "job") == 0) return job(argc, argv);
    if (argc > 1 && strcmp(argv[1], "stress") == 0) return stress(argc, argv);
    fprintf(stderr, "usage: %s job WCET_US PERIOD_US DEADLINE_US SECONDS SEED GO [HIGH] | stress MIB SECONDS GO\n", argv[0]);
    return 2;
}
