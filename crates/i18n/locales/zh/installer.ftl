# The Windows installer's own words (see en/installer.ftl).
installer-shortcut-comment = 诊所为您安排的驾驶练习。
installer-finish = telerehab 已经装好。请插上方向盘。然后从“开始”菜单打开 telerehab。
