# Draws lambda_work_precision.py's TSV: mean |lambda - lambda_ref| against CPU
# seconds, log-log. usage: Rscript lambda_work_precision.R IN.tsv OUT.png
a <- commandArgs(trailingOnly = TRUE)
d <- read.delim(a[1], stringsAsFactors = FALSE, colClasses = c(dt = "character"))
d <- d[d$blowups == 0, ]
png(a[2], width = 900, height = 560, res = 120)
sp <- d[d$who == "springpend", ]; pe <- d[d$who == "numba", ]
plot(sp$cpu, sp$mean, log = "xy", type = "b", pch = 19, col = "steelblue",
     xlim = c(0.3, 30), ylim = c(0.01, 0.05),
     xlab = "CPU time, s (user + sys; 512 angles, T = 200 s)",
     ylab = "mean |lambda - lambda_ref| over the grid (1/s)",
     main = "chaotic.ini, RK4 + tangent: lambda(T = 200 s) against dt = 1.25e-4")
text(sp$cpu, sp$mean, paste("dt", sp$dt), pos = 3, cex = 0.75)
points(pe$cpu, pe$mean, pch = 15, col = "firebrick", cex = 1.3)
text(pe$cpu, pe$mean, paste("numba peer, dt", pe$dt), pos = 1, cex = 0.75, col = "firebrick")
legend("topright", c("springpend sweep", "numba peer (both cores)"), pch = c(19, 15),
       col = c("steelblue", "firebrick"), cex = 0.8, bty = "n")
grid()
invisible(dev.off())
