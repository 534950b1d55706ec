"""The Tessellate command's background process: `freecadcmd -c` runs main() on a job folder
written by tessellate.write_job (runner.tessellate_job builds the command line).

Prints one progress line per B-rep face meshed (`tessellate: k/n faces`, read by the progress
panel) and exits 1 with a one-line error on failure (the panel shows the last lines).
"""

import os
import sys


def main(job_path):
    try:
        from thermodec_freecad import tessellate
        last = [-1]

        def progress(done, total):
            percent = 100 * done // max(total, 1)
            if percent != last[0]:  # at most 101 lines, however many faces
                last[0] = percent
                print("tessellate: %d/%d faces" % (done, total), flush=True)

        print("tessellate: meshing the B-rep faces of %s (Mefisto)" % job_path, flush=True)
        count = tessellate.run_job(job_path, progress)
        print("tessellate: %d triangles" % count, flush=True)
    except Exception as e:  # one line for the panel, never a traceback
        print("tessellate: error: %s" % e, flush=True)
        sys.stdout.flush()
        os._exit(1)
    sys.stdout.flush()
    os._exit(0)  # at once: nothing of FreeCAD's to tear down
