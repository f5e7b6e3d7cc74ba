import csv, json, statistics, sys
def stats(path):
    f=list(csv.DictReader(open(path+'/forces.csv')))
    h=f[len(f)//2:]
    fc=[float(x['fc_n_per_mm'])*1e3 for x in h]; ff=[float(x['ff_n_per_mm'])*1e3 for x in h]
    a=json.load(open(path+'/summary.json'))['energy_audit']
    return len(h), statistics.mean(fc), statistics.pstdev(fc), statistics.mean(ff), a['booked_over_workpiece_work'], a['tool_work_j'], a['workpiece_work_j'], a['booked_j']
for p in sys.argv[1:]:
    n,fc,sd,ff,r,w,wp,b=stats(p)
    print(f"{p}: n {n} F_c {fc:.0f} (sd {sd:.0f}) F_f {ff:.0f} booked/W_p {r:.3f} W {w:.2f} W_p {wp:.2f} booked {b:.2f}")
