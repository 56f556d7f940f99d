// Experiment: cost of handing M cache lines from a writer core to a reader core, per pattern.
#include <pthread.h>
#include <sched.h>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>
#include <thread>
#include <algorithm>
#include <random>
#include <cstring>
#include <immintrin.h>
static void pin(int c){cpu_set_t s;CPU_ZERO(&s);CPU_SET(c,&s);pthread_setaffinity_np(pthread_self(),sizeof(s),&s);}
struct alignas(64) L { double v[8]; };
struct Bar { std::atomic<int> a{0}, g{0}; void wait(){int gen=g.load(std::memory_order_acquire); if(a.fetch_add(1)+1==2){a.store(0);g.fetch_add(1);return;} while(g.load(std::memory_order_acquire)==gen){} } };
int main(int argc,char**argv){
  int M = argc>1?atoi(argv[1]):1500; int iters = argc>2?atoi(argv[2]):400;
  std::vector<L> buf(M*4); // spread: lines used = every line of first M (seq) 
  std::vector<int> seq(M), rnd(M);
  for(int i=0;i<M;i++) seq[i]=i;
  rnd=seq; std::mt19937 g(1); std::shuffle(rnd.begin(),rnd.end(),g);
  const char* names[]={"seq","rand","rand_pf8","seq_rw","seq_nt","seq_pfw"};
  for(int pat=0;pat<6;pat++){
    const std::vector<int>& ord = (pat==1||pat==2)?rnd:seq;
    Bar b; std::vector<double> wt, rt; volatile double sink=0;
    std::thread w([&]{pin(0); for(int it=0;it<iters;it++){ auto t0=std::chrono::steady_clock::now(); if(pat==4){ for(int k=0;k<M;k++){ L& l=buf[ord[k]]; __m512d x=_mm512_set1_pd(double(it)); _mm512_stream_pd(l.v,x);} _mm_sfence(); } else if(pat==5){ for(int k=0;k<M;k++){ if(k+16<M) __builtin_prefetch(&buf[ord[k+16]],1); L& l=buf[ord[k]]; for(int q=0;q<3;q++) l.v[q]+=1.0;} } else for(int k=0;k<M;k++){ L& l=buf[ord[k]]; for(int q=0;q<3;q++) l.v[q]+=1.0;} wt.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now()-t0).count()); b.wait(); b.wait(); }});
    std::thread r([&]{pin(1); for(int it=0;it<iters;it++){ b.wait(); auto t0=std::chrono::steady_clock::now(); double s=0; for(int k=0;k<M;k++){ if(pat==2 && k+8<M) __builtin_prefetch(&buf[ord[k+8]]); const L& l=buf[ord[k]]; s+=l.v[0]+l.v[1]+l.v[2]; } sink=s; rt.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now()-t0).count()); b.wait(); }});
    w.join(); r.join();
    std::sort(wt.begin(),wt.end()); std::sort(rt.begin(),rt.end());
    printf("%-9s M=%d write %.1f us (%.0f ns/line)  read %.1f us (%.0f ns/line)\n", names[pat], M, wt[iters/2]*1e6, wt[iters/2]*1e9/M, rt[iters/2]*1e6, rt[iters/2]*1e9/M);
  }
}
