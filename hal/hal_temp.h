/* Controller board temperature sensor. */
#ifndef HAL_TEMP_H
#define HAL_TEMP_H

float hal_temp_board_c(void);

#endif
