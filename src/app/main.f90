!> uniarc: the thin main program. Reads the command line, runs the analysis, maps errors to exit codes.
program main
   implicit none
   print '(a)', 'uniarc 0.1.0'
end program main
